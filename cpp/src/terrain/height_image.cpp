#include "ifsforge/terrain/height_image.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "terrain_cells.h"

namespace ifsforge {
namespace {

struct Vertex {
  float x, y;  // pixel coordinates: pixel centres at integers, y down
};

/// Edge function of the directed edge a -> b at p, computed from the lexicographically first
/// endpoint so that the two triangles sharing an edge see exactly opposite values: every pixel
/// centre belongs to exactly one triangle (with the top-left rule for centres on an edge).
inline double edge(const Vertex& a, const Vertex& b, double px, double py) {
  const bool swap = b.x < a.x || (b.x == a.x && b.y < a.y);
  const Vertex& p = swap ? b : a;
  const Vertex& q = swap ? a : b;
  const double e = (double(q.x) - p.x) * (py - p.y) - (double(q.y) - p.y) * (px - p.x);
  return swap ? -e : e;
}

/// Whether a centre exactly on edge a -> b belongs to this triangle: of the two directions an
/// edge is traversed in, exactly one passes.
inline bool owns(const Vertex& a, const Vertex& b) {
  const float dx = b.x - a.x, dy = b.y - a.y;
  return dy > 0 || (dy == 0 && dx < 0);
}

/// `outline` flags the edges ab, bc, ca that lie on the terrain's outline: centres on them (to
/// rounding) belong to the triangle, since no neighbour can claim them.
void raster_triangle(const Vertex& a, const Vertex& b, const Vertex& c, float ha, float hb, float hc,
                     const std::array<bool, 3>& outline, int y0, int y1, int width, float* out,
                     std::uint8_t* covered) {
  // Triangles arrive counter-clockwise seen from above; in pixel coordinates (y down) that is
  // clockwise, so interior points have all edge functions negative: flip to positive.
  const double area = -edge(a, b, c.x, c.y);
  if (!(area > 0)) return;  // degenerate (the centre of a circular grid)
  // The box reaches 1/1000 of a pixel further, for centres on the outline within rounding.
  const double reach = 1e-3;
  const int xs = std::max(0, int(std::ceil(std::min({a.x, b.x, c.x}) - reach)));
  const int xe = std::min(width - 1, int(std::floor(std::max({a.x, b.x, c.x}) + reach)));
  const int ys = std::max(y0, int(std::ceil(std::min({a.y, b.y, c.y}) - reach)));
  const int ye = std::min(y1 - 1, int(std::floor(std::max({a.y, b.y, c.y}) + reach)));
  const bool own_ab = owns(b, a), own_bc = owns(c, b), own_ca = owns(a, c);
  auto slack = [](bool on_outline, const Vertex& p, const Vertex& q) {
    return on_outline ? 1e-4 * (std::fabs(q.x - p.x) + std::fabs(q.y - p.y)) : 0.0;
  };
  const double slack_a = slack(outline[1], b, c), slack_b = slack(outline[2], c, a), slack_c = slack(outline[0], a, b);
  for (int y = ys; y <= ye; ++y)
    for (int x = xs; x <= xe; ++x) {
      double wa = -edge(b, c, x, y), wb = -edge(c, a, x, y), wc = -edge(a, b, x, y);
      if (wa < -slack_a || wb < -slack_b || wc < -slack_c) continue;
      if (wa < 0 || wb < 0 || wc < 0) {  // on the outline, within rounding
        wa = std::max(wa, 0.0), wb = std::max(wb, 0.0), wc = std::max(wc, 0.0);
      } else if ((wa == 0 && !own_bc && !outline[1]) || (wb == 0 && !own_ca && !outline[2]) ||
                 (wc == 0 && !own_ab && !outline[0])) {
        continue;
      }
      const double sum = wa + wb + wc;
      const std::size_t i = std::size_t(y) * width + x;
      out[i] = float((wa * ha + wb * hb + wc * hc) / sum);
      covered[i] = 1;
    }
}


}  // namespace

Image height_image(const Terrain& t, int width, int height, int threads) {
  if (t.columns < 2 || t.rows < 2 || t.heights.size() != std::size_t(t.columns) * t.rows)
    throw InputError("height image: the terrain has no samples");
  const double lo = t.min_height, range = double(t.max_height) - t.min_height;
  const double scale = range > 0 ? 1.0 / range : 0.0;

  if (t.grid == TerrainGrid::Regular) {
    if ((width && width != t.columns) || (height && height != t.rows))
      throw InputError("height image: a regular terrain's image is its " + std::to_string(t.columns) + " x " +
                       std::to_string(t.rows) + " samples; make the terrain at the size you need");
    Image image(t.columns, t.rows, 1);
    for (int r = 0; r < t.rows; ++r)
      for (int c = 0; c < t.columns; ++c)
        image.at(c, t.rows - 1 - r, 0) = float((t.height(r, c) - lo) * scale);
    return image;
  }

  const bool circular = t.grid == TerrainGrid::Circular;
  if (width == 0) width = circular ? 2 * t.rows - 1 : t.columns;
  if (height == 0) height = circular ? 2 * t.rows - 1 : t.rows;
  if (width < 2 || height < 2 || width > 65535 || height > 65535)
    throw InputError("height image: 2 to 65535 pixels per side, got " + std::to_string(width) + " x " +
                     std::to_string(height));
  const std::size_t samples = t.heights.size(), pixels = std::size_t(width) * height;
  check_memory(double(samples) * 8.0 + double(pixels) * 5.0 + double(samples) * 12.0,
               "a " + std::to_string(width) + " x " + std::to_string(height) + " height image");

  // Vertices in pixel coordinates.
  const std::array<double, 4> box = t.extent();
  const double sx = (width - 1) / (box[2] - box[0]), sy = (height - 1) / (box[3] - box[1]);
  std::vector<Vertex> vertex(samples);
  const std::size_t band_rows = 64;
  parallel_jobs((t.rows + band_rows - 1) / band_rows, threads, [&](std::size_t job, int) {
    for (int r = int(job * band_rows); r < std::min<int>(t.rows, int((job + 1) * band_rows)); ++r)
      for (int c = 0; c < t.columns; ++c) {
        const std::array<double, 3> p = t.position(r, c);
        vertex[std::size_t(r) * t.columns + c] = {float((p[0] - box[0]) * sx), float((box[3] - p[1]) * sy)};
      }
  });

  // Bin the cells by the bands of image rows their bounding boxes touch, in cell order, so
  // that each band is drawn by one job and the image never depends on the thread count.
  const int band = 16, bands = (height + band - 1) / band;
  const std::size_t across = detail::cells_across(t), cells = across * (t.rows - 1);
  if (cells >= (std::size_t(1) << 32)) throw InputError("height image: the terrain has too many cells to bin");
  auto band_range = [&](std::size_t cell) {
    const std::size_t r = cell / across, c = cell % across, c1 = (c + 1) % t.columns;
    const std::size_t corner[4] = {r * t.columns + c, r * t.columns + c1, (r + 1) * t.columns + c1,
                                   (r + 1) * t.columns + c};
    float y0 = vertex[corner[0]].y, y1 = y0;
    for (std::size_t k : corner) y0 = std::min(y0, vertex[k].y), y1 = std::max(y1, vertex[k].y);
    const int b0 = std::clamp(int(std::ceil(y0 - 1e-3)), 0, height - 1) / band;
    const int b1 = std::clamp(int(std::floor(y1 + 1e-3)), 0, height - 1) / band;
    return std::pair<int, int>(b0, std::max(b0, b1));
  };
  std::vector<std::size_t> start(bands + 1, 0);
  for (std::size_t cell = 0; cell < cells; ++cell) {
    const auto [b0, b1] = band_range(cell);
    for (int b = b0; b <= b1; ++b) ++start[b + 1];
  }
  for (int b = 0; b < bands; ++b) start[b + 1] += start[b];
  check_memory(double(start[bands]) * 4.0, "the height image's cell bins");
  std::vector<std::uint32_t> binned(start[bands]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t cell = 0; cell < cells; ++cell) {
    const auto [b0, b1] = band_range(cell);
    for (int b = b0; b <= b1; ++b) binned[fill[b]++] = std::uint32_t(cell);
  }

  Image image(width, height, 1);
  std::vector<std::uint8_t> covered(pixels, 0);
  std::vector<float> normalised(samples);
  for (std::size_t i = 0; i < samples; ++i) normalised[i] = float((t.heights[i] - lo) * scale);
  parallel_jobs(bands, threads, [&](std::size_t b, int) {
    const int y0 = int(b) * band, y1 = std::min(height, y0 + band);
    for (std::size_t k = start[b]; k < start[b + 1]; ++k) {
      const std::size_t cell = binned[k];
      const std::size_t r = cell / across, c = cell % across;
      const auto tris = detail::cell_triangles(t, r, c);
      // Rectangular outlines: (a, b, c) has the cell's south and east edges, (a, c, d) its
      // north and west edges. (A circle's outside is filled below.)
      const bool rect = !circular;
      const std::array<std::array<bool, 3>, 2> outline = {
          {{rect && r == 0, rect && c + 2 == std::size_t(t.columns), false},
           {false, rect && r + 2 == std::size_t(t.rows), rect && c == 0}}};
      for (int k = 0; k < 2; ++k) {
        const auto& tri = tris[k];
        raster_triangle(vertex[tri[0]], vertex[tri[1]], vertex[tri[2]], normalised[tri[0]], normalised[tri[1]],
                        normalised[tri[2]], outline[k], y0, y1, width, image.pixels.data(), covered.data());
      }
    }
  });

  // Pixels the surface does not reach: a circle's outside takes its outer circle's height at
  // the same angle; anything else (never expected) its left neighbour.
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t i = std::size_t(y) * width + x;
      if (covered[i]) continue;
      if (circular) {
        const double wx = box[0] + x / sx, wy = box[3] - y / sy;
        const double turn = std::atan2(wy, wx) / (2.0 * M_PI);
        const double p = (turn - std::floor(turn)) * t.columns;
        const int c0 = std::min(int(p), t.columns - 1), c1 = (c0 + 1) % t.columns;
        const std::size_t outer = std::size_t(t.rows - 1) * t.columns;
        image.pixels[i] = float(normalised[outer + c0] + (normalised[outer + c1] - normalised[outer + c0]) * (p - c0));
      } else {
        image.pixels[i] = x > 0 ? image.pixels[i - 1] : (y > 0 ? image.pixels[i - width] : 0.0f);
      }
    }
  return image;
}

}  // namespace ifsforge
