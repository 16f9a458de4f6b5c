#include "ifsforge/render/frame.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/model/attractor_points.h"

namespace ifsforge {

void check_image_size(int width, int height) {
  if (width < 1 || height < 1 || width > 65535 || height > 65535)
    throw InputError("image size " + std::to_string(width) + "x" + std::to_string(height) +
                     " is outside 1..65535 per side");
}

Frame Frame::fit(const Ifs& ifs, int width, int height, const std::optional<Window>& window,
                 const View& view, double margin, int threads) {
  check_image_size(width, height);
  Frame f;
  f.width_ = width;
  f.height_ = height;
  f.spatial_ = ifs.spatial_dims();
  if (f.spatial_ == 2) {
    f.projection_ = {{{1, 0, 0}, {0, 1, 0}}};
  } else {
    const double y = view.yaw * M_PI / 180.0, p = view.pitch * M_PI / 180.0;
    f.projection_ = {{{std::cos(y), std::sin(y), 0.0},
                      {-std::sin(p) * std::sin(y), std::sin(p) * std::cos(y), std::cos(p)}}};
    const auto& u = f.projection_[0];
    const auto& v = f.projection_[1];
    f.toward_viewer_ = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  }
  Window w;
  if (window) {
    w = *window;
    if (!(std::isfinite(w.xmin) && std::isfinite(w.xmax) && std::isfinite(w.ymin) &&
          std::isfinite(w.ymax)) || !(w.xmax > w.xmin) || !(w.ymax > w.ymin))
      throw InputError("the window must be finite with xmin < xmax and ymin < ymax");
  } else {
    ifs.require_attractor();
    const Classification kind = ifs.classify();
    const bool hyperbolic = kind == Classification::Hyperbolic;
    // Polar systems stay in a bounded disc (Eq. 30): all their samples count, and a thin
    // margin takes the extremes no sample reached (there is no affine support function).
    const bool polar = kind == Classification::LocallyContractive;
    const std::size_t samples = 1u << 15;  // extremes converge fast; the margin covers the rest
    if (hyperbolic || polar) {
      // Quantiles 0 and 1: the least and greatest projections, by one pass (on `threads` cores)
      // with no list of them; a hyperbolic system's extreme points after the samples.
      double lo[2], hi[2];
      sample_extent(ifs, samples, 0xF7A3E, 2, [&](const Point& q, double* uv) {
        const auto p = f.project(q);
        uv[0] = p[0];
        uv[1] = p[1];
      }, lo, hi, threads);
      if (hyperbolic)
        for (const Point& q : attractor_extremes(ifs)) {
          const auto uv = f.project(q);
          for (int c = 0; c < 2; ++c) {
            if (uv[c] < lo[c]) lo[c] = uv[c];
            if (hi[c] < uv[c]) hi[c] = uv[c];
          }
        }
      w = {lo[0], lo[1], hi[0], hi[1]};
    } else {
      std::vector<double> us, vs;
      us.reserve(samples);
      vs.reserve(samples);
      sample_attractor(ifs, samples, 0xF7A3E, [&](const Point& q) {
        const auto uv = f.project(q);
        us.push_back(uv[0]);
        vs.push_back(uv[1]);
      });
      w = {quantile(us, 0.001), quantile(vs, 0.001), quantile(us, 0.999), quantile(vs, 0.999)};
    }
    double dx = w.xmax - w.xmin, dy = w.ymax - w.ymin;
    const double extent = std::max({dx, dy, 1e-9 * (std::abs(w.xmin) + std::abs(w.ymin)), 1e-12});
    dx = std::max(dx, extent * 1e-3);
    dy = std::max(dy, extent * 1e-3);
    const double pad = hyperbolic ? 0.0 : polar ? 0.02 : margin;
    w = {w.xmin - pad * dx, w.ymin - pad * dy, w.xmax + pad * dx, w.ymax + pad * dy};
  }
  // Keep pixels square: grow the window's short side about its centre.
  const double scale = std::max((w.xmax - w.xmin) / width, (w.ymax - w.ymin) / height);
  const double cx = 0.5 * (w.xmin + w.xmax), cy = 0.5 * (w.ymin + w.ymax);
  f.window_ = {cx - 0.5 * scale * width, cy - 0.5 * scale * height, cx + 0.5 * scale * width,
               cy + 0.5 * scale * height};
  f.sx_ = f.sy_ = 1.0 / scale;
  return f;
}

}  // namespace ifsforge
