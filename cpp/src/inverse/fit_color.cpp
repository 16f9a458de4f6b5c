#include "ifsforge/inverse/fit_color.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/inverse/collage.h"

namespace ifsforge {
namespace {

// One colour row of one map: c_r, c_g, c_b (the colour block's row), gx, gy (the gradient), o.
constexpr int kUnknowns = 6;
using Row = std::array<double, kUnknowns>;
using Free = std::array<bool, kUnknowns>;

/// One pixel pair of map i: the picture's colour at p, where p lies in the plane, and the
/// picture's colour at w_i(p).
struct ColorPair {
  std::array<float, 3> from, to;
  std::array<double, 2> at;
};

double predict(const Row& r, const ColorPair& p) {
  return r[0] * p.from[0] + r[1] * p.from[1] + r[2] * p.from[2] + r[3] * p.at[0] + r[4] * p.at[1] + r[5];
}

/// Least squares of to = c . from + gx x + gy y + o over the pairs, the unknowns flagged free
/// solved and the others held at `fixed` (normal equations with a tiny ridge, which only
/// matters when the pairs leave an unknown undetermined, e.g. a copy of uniform colour).
Row solve_channel(const std::vector<ColorPair>& pairs, int channel, const Free& free, const Row& fixed) {
  std::vector<int> idx;  // the free unknowns, in order
  for (int k = 0; k < kUnknowns; ++k)
    if (free[k]) idx.push_back(k);
  const int m = static_cast<int>(idx.size());
  double n[kUnknowns][kUnknowns + 1] = {};  // the normal equations on the free unknowns
  for (const ColorPair& p : pairs) {
    const double row[kUnknowns] = {p.from[0], p.from[1], p.from[2], p.at[0], p.at[1], 1.0};
    double rhs = p.to[channel];
    for (int k = 0; k < kUnknowns; ++k)
      if (!free[k]) rhs -= fixed[k] * row[k];
    for (int a = 0; a < m; ++a) {
      for (int b = 0; b < m; ++b) n[a][b] += row[idx[a]] * row[idx[b]];
      n[a][m] += row[idx[a]] * rhs;
    }
  }
  for (int a = 0; a < m; ++a) n[a][a] += 1e-9 * (1.0 + n[a][a]);
  // Gaussian elimination with partial pivoting, then back substitution.
  for (int i = 0; i < m; ++i) {
    int pivot = i;
    for (int r = i + 1; r < m; ++r)
      if (std::abs(n[r][i]) > std::abs(n[pivot][i])) pivot = r;
    std::swap(n[i], n[pivot]);
    for (int r = i + 1; r < m; ++r) {
      const double f = n[r][i] / n[i][i];
      for (int c = i; c <= m; ++c) n[r][c] -= f * n[i][c];
    }
  }
  Row x = fixed;
  for (int i = m - 1; i >= 0; --i) {
    double v = n[i][m];
    for (int c = i + 1; c < m; ++c) v -= n[i][c] * x[idx[c]];
    x[idx[i]] = v / n[i][i];
  }
  return x;
}

/// The map extended to (x, y, r, g, b) with colour rows `rows`.
AffineMap colour_map(const AffineMap& spatial, const std::array<Row, 3>& rows) {
  AffineMap m(5);
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 2; ++c) m.a(r, c) = spatial.a(r, c);
    m.b(r) = spatial.b(r);
  }
  for (int ch = 0; ch < 3; ++ch) {
    for (int c = 0; c < 3; ++c) m.a(2 + ch, 2 + c) = rows[ch][c];
    m.a(2 + ch, 0) = rows[ch][3];
    m.a(2 + ch, 1) = rows[ch][4];
    m.b(2 + ch) = rows[ch][5];
  }
  return m;
}

}  // namespace

bool has_color(const Image& image) {
  if (image.channels < 3) return false;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (image.at(x, y, 0) != image.at(x, y, 1) || image.at(x, y, 1) != image.at(x, y, 2)) return true;
  return false;
}

PixelSet color_foreground(const Image& image, double tolerance) {
  if (image.width < 1 || image.height < 1 || image.channels < 1) throw InputError("the target picture is empty");
  if (!(tolerance >= 0 && tolerance < 1)) throw InputError("the color tolerance must lie in [0, 1), got " + std::to_string(tolerance));
  const int c = image.channels;
  // The border's usual colour: the median of each channel over the border pixels.
  std::vector<float> border_color(c);
  for (int ch = 0; ch < c; ++ch) {
    std::vector<float> v;
    for (int x = 0; x < image.width; ++x)
      for (int y : {0, image.height - 1}) v.push_back(image.at(x, y, ch));
    for (int y = 1; y + 1 < image.height; ++y)
      for (int x : {0, image.width - 1}) v.push_back(image.at(x, y, ch));
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    border_color[ch] = v[v.size() / 2];
  }
  PixelSet out{image.width, image.height, std::vector<std::uint8_t>(std::size_t(image.width) * image.height)};
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      bool unlike = false;
      for (int ch = 0; ch < c && !unlike; ++ch) unlike = std::abs(image.at(x, y, ch) - border_color[ch]) > tolerance;
      out.cells[std::size_t(y) * image.width + x] = unlike;
    }
  const std::size_t n = out.count();
  if (n == 0 || n == out.cells.size())
    throw InputError("the target picture has no shape: no pixel's color differs from the border's by more than " +
                     std::to_string(tolerance));
  return out;
}

ColorFitResult fit_color(const Ifs& shape_system, const Image& picture, const PixelSet& shape,
                           const ColorFitOptions& o) {
  if (shape_system.layout().text() != "xy")
    throw InputError("fit_color extends a planar xy system; '" + shape_system.name() + "' has layout " +
                     shape_system.layout().text());
  if (picture.channels < 3) throw InputError("a color fit needs an RGB or RGBA picture, got " +
                                             std::to_string(picture.channels) + " channel(s)");
  if (shape.width != picture.width || shape.height != picture.height)
    throw InputError("the shape (" + std::to_string(shape.width) + "x" + std::to_string(shape.height) +
                     ") and the picture (" + std::to_string(picture.width) + "x" + std::to_string(picture.height) +
                     ") differ in size");
  if (shape.count() == 0) throw InputError("the target has no pixels");
  if (!(o.max_contraction > 0 && o.max_contraction < 1))
    throw InputError("the largest contraction must lie in (0, 1), got " + std::to_string(o.max_contraction));
  const Frame frame = target_frame(shape_system, shape, std::nullopt);
  const auto maps = pixel_maps(shape_system, frame);
  const double h = frame.pixel_size(), xmin = frame.window().xmin, ymax = frame.window().ymax;
  auto colour = [&](int x, int y) {
    return std::array<float, 3>{picture.at(x, y, 0), picture.at(x, y, 1), picture.at(x, y, 2)};
  };
  ColorFitResult result;
  std::vector<AffineMap> out;
  std::array<double, 3> squared{};
  for (std::size_t i = 0; i < maps.size(); ++i) {
    // The collage per channel: pairs (p, w_i(p)) with both in the shape.
    std::vector<ColorPair> pairs;
    const PixelMap& m = maps[i];
    for (int y = 0; y < shape.height; ++y)
      for (int x = 0; x < shape.width; ++x) {
        if (!shape.cells[std::size_t(y) * shape.width + x]) continue;
        const double px = x + 0.5, py = y + 0.5;
        const double qx = std::floor(m[0] * px + m[1] * py + m[2]), qy = std::floor(m[3] * px + m[4] * py + m[5]);
        if (!(qx >= 0 && qy >= 0 && qx < shape.width && qy < shape.height)) continue;
        const int ix = static_cast<int>(qx), iy = static_cast<int>(qy);
        if (!shape.cells[std::size_t(iy) * shape.width + ix]) continue;
        pairs.push_back({colour(x, y), colour(ix, iy), {xmin + px * h, ymax - py * h}});
      }
    std::array<Row, 3> rows{};
    for (int ch = 0; ch < 3; ++ch) {
      if (pairs.empty()) break;  // a copy off the shape: colour 0 (its points never show)
      Free free = {o.mixing, o.mixing, o.mixing, o.positional, o.positional, true};
      free[ch] = true;
      rows[ch] = solve_channel(pairs, ch, free, Row{});
    }
    // The colour block contracts by its spectral norm (Eq. 8-9 in 3D): shrink it onto
    // max_contraction when it exceeds it, and refit the gradient and offset to that block.
    AffineMap block(3);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) block.a(r, c) = rows[r][c];
    const double sc = block.contraction_factor();
    if (sc > o.max_contraction && !pairs.empty())
      for (int ch = 0; ch < 3; ++ch) {
        Row fixed{};
        for (int c = 0; c < 3; ++c) fixed[c] = rows[ch][c] * o.max_contraction / sc;
        rows[ch] = solve_channel(pairs, ch, {false, false, false, o.positional, o.positional, true}, fixed);
      }
    // The whole map (block triangular) may still stretch through the gradient: shrink it and
    // refit the offsets until the map contracts by at most max_contraction.
    AffineMap w = colour_map(shape_system.map(i), rows);
    for (int step = 0; step < 60 && w.contraction_factor() > o.max_contraction; ++step) {
      for (int ch = 0; ch < 3; ++ch) {
        rows[ch][3] *= 0.8, rows[ch][4] *= 0.8;
        if (step == 59) rows[ch][3] = rows[ch][4] = 0;
        if (!pairs.empty()) rows[ch] = solve_channel(pairs, ch, {false, false, false, false, false, true}, rows[ch]);
      }
      w = colour_map(shape_system.map(i), rows);
    }
    for (const ColorPair& p : pairs)
      for (int ch = 0; ch < 3; ++ch) {
        const double e = p.to[ch] - predict(rows[ch], p);
        squared[ch] += e * e;
      }
    result.samples += pairs.size();
    out.push_back(w);
  }
  for (int ch = 0; ch < 3; ++ch) result.collage_error[ch] = result.samples ? std::sqrt(squared[ch] / result.samples) : 0.0;
  Ifs system(shape_system.name(), ChannelLayout("xy+rgb"), out, shape_system.probabilities());
  system.set_description(shape_system.description());
  system.set_render_defaults(shape_system.render_defaults());
  result.system = std::move(system);
  return result;
}

}  // namespace ifsforge
