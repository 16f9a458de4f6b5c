#pragma once
/// @file Where an image sits in the space of an IFS: a projection of the spatial
/// coordinates onto a plane, a window on that plane, and the pixel grid.
#include <array>
#include <cmath>
#include <optional>

#include "ifsforge/model/ifs.h"

namespace ifsforge {

/// @brief [xmin, xmax] x [ymin, ymax] on the image plane.
struct Window {
  double xmin = 0, ymin = 0, xmax = 1, ymax = 1;
};

/// @brief Orthographic view of a 3D system (degrees): u = cos(yaw) x + sin(yaw) y,
/// v = sin(pitch) (-sin(yaw) x + cos(yaw) y) + cos(pitch) z: a positive pitch looks down from
/// above (far points appear higher). 2D systems ignore it.
struct View {
  double yaw = 0, pitch = 0;
};

/// @brief An affine map from an IFS's space straight to continuous pixel coordinates: a
/// frame's to_pixel after a piece's map, composed once for the many points of one piece.
struct PixelTransform {
  int dim = 0;
  std::array<std::array<double, kMaxDim>, 2> a{};
  std::array<double, 2> b{};
  /// @brief out = this o w: a piece's map from its parent's, one level down a recursion.
  void compose(const AffineMap& w, PixelTransform& out) const {
    if (dim == 2) return compose_in<2>(w, out);  // unrolled: a recursion composes at every node
    if (dim == 3) return compose_in<3>(w, out);
    compose_in<0>(w, out);
  }
  /// @brief The pixel box [lo, hi) of the image of the box centre +- half (dim coordinates).
  void box(const double* center, const double* half, double* lo, double* hi) const {
    if (dim == 2) return box_in<2>(center, half, lo, hi);
    if (dim == 3) return box_in<3>(center, half, lo, hi);
    box_in<0>(center, half, lo, hi);
  }

 private:
  /// D: the dimension known when compiled (0: dim).
  template <int D>
  void compose_in(const AffineMap& w, PixelTransform& out) const {
    const int n = D ? D : dim;
    out.dim = n;
    for (int axis = 0; axis < 2; ++axis) {
      double offset = b[axis];
      for (int k = 0; k < n; ++k) offset += a[axis][k] * w.b(k);
      out.b[axis] = offset;
      for (int c = 0; c < n; ++c) {
        double v = 0.0;
        for (int k = 0; k < n; ++k) v += a[axis][k] * w.a(k, c);
        out.a[axis][c] = v;
      }
    }
  }
  template <int D>
  void box_in(const double* center, const double* half, double* lo, double* hi) const {
    const int n = D ? D : dim;
    for (int axis = 0; axis < 2; ++axis) {
      double c = b[axis], extent = 0.0;
      for (int k = 0; k < n; ++k) {
        c += a[axis][k] * center[k];
        extent += std::abs(a[axis][k]) * half[k];
      }
      lo[axis] = c - extent;
      hi[axis] = c + extent;
    }
  }
};

class Frame {
 public:
  /// @brief Image plane coordinates (u, v) of the spatial part of p.
  std::array<double, 2> project(const Point& p) const {
    double u = 0, v = 0;
    for (int c = 0; c < spatial_; ++c) {
      u += projection_[0][c] * p[c];
      v += projection_[1][c] * p[c];
    }
    return {u, v};
  }
  /// @brief Distance towards the viewer along the view axis (u x v) for 3D systems; 0 in 2D.
  double depth(const Point& p) const {
    double d = 0;
    for (int c = 0; c < spatial_; ++c) d += toward_viewer_[c] * p[c];
    return d;
  }
  const std::array<double, 3>& toward_viewer() const { return toward_viewer_; }
  /// @brief Continuous pixel coordinates (x right, y down; pixel (i, j) covers [i, i+1) x [j, j+1)).
  std::array<double, 2> to_pixel(const Point& p) const {
    const auto uv = project(p);
    return {(uv[0] - window_.xmin) * sx_, (window_.ymax - uv[1]) * sy_};
  }
  /// @brief to_pixel(m(p)) as one affine map, into `out` (coefficients up to m's dimension:
  /// a recursion sets one per node).
  void pixel_transform(const AffineMap& m, PixelTransform& out) const {
    out.dim = m.dim();
    const double scale[2] = {sx_, -sy_};
    for (int axis = 0; axis < 2; ++axis) {
      double f[3];
      for (int r = 0; r < spatial_; ++r) f[r] = scale[axis] * projection_[axis][r];
      double offset = axis == 0 ? -window_.xmin * sx_ : window_.ymax * sy_;
      for (int r = 0; r < spatial_; ++r) offset += f[r] * m.b(r);
      out.b[axis] = offset;
      for (int c = 0; c < out.dim; ++c) {
        double v = 0.0;
        for (int r = 0; r < spatial_; ++r) v += f[r] * m.a(r, c);
        out.a[axis][c] = v;
      }
    }
  }
  int width() const { return width_; }
  int height() const { return height_; }
  const Window& window() const { return window_; }
  int spatial_dims() const { return spatial_; }
  const std::array<std::array<double, 3>, 2>& projection() const { return projection_; }
  /// @brief Width of one pixel on the image plane.
  double pixel_size() const { return 1.0 / sx_; }

  /// @brief A frame for `ifs`: the given window (stretched to the image's aspect ratio) or,
  /// without one, the attractor's projected bounds: exact for a hyperbolic system (no margin,
  /// so a grid-aligned attractor such as a carpet at 3^k pixels fills exactly its pixels),
  /// else sampled quantiles with a relative `margin` on each side. The sample walks on up to
  /// `threads` cores (0: all) where it can: the same frame.
  static Frame fit(const Ifs& ifs, int width, int height, const std::optional<Window>& window,
                   const View& view = {}, double margin = kMargin, int threads = 1);
  /// The relative margin of a sampled (not hyperbolic) frame.
  static constexpr double kMargin = 0.03;

 private:
  int width_ = 0, height_ = 0, spatial_ = 2;
  Window window_;
  std::array<std::array<double, 3>, 2> projection_{};
  std::array<double, 3> toward_viewer_{};
  double sx_ = 1, sy_ = 1;
};

/// @brief Refuses image sizes outside 1..65535 per side (PNG's practical limit).
void check_image_size(int width, int height);

}  // namespace ifsforge
