#include "ifsforge/render/accurate_fractal.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/leaf_plotter.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/piece_work.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {
namespace {

/// A tile M(Q): the composed map M = t_a1 o ... o t_ak (flat) of its address and its mass.
struct Tile {
  double map[composed::size(kMaxDim)];
  double mass;
  int depth;
};

/// Solves a x = b for a (n x n, row-major) by Gauss-Jordan with partial pivoting.
std::vector<double> solve(std::vector<double> a, std::vector<double> b, int n) {
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    for (int r = col + 1; r < n; ++r)
      if (std::abs(a[r * n + col]) > std::abs(a[pivot * n + col])) pivot = r;
    if (std::abs(a[pivot * n + col]) < 1e-14)
      throw InputError("accurate fractal rendering: the channels' self-similarity equations (Eq. 68) are singular");
    for (int c = 0; c < n; ++c) std::swap(a[col * n + c], a[pivot * n + c]);
    std::swap(b[col], b[pivot]);
    for (int r = 0; r < n; ++r) {
      if (r == col) continue;
      const double f = a[r * n + col] / a[col * n + col];
      for (int c = col; c < n; ++c) a[r * n + c] -= f * a[col * n + c];
      b[r] -= f * b[col];
    }
  }
  for (int r = 0; r < n; ++r) b[r] /= a[r * n + r];
  return b;
}

}  // namespace

Capabilities AccurateFractal::capabilities() const {
  // Tiles split until they fit a pixel: a map that expands never gets there; overlapping
  // tiles are bounded by the estimate in draw().
  using C = Capabilities;
  return {C::Overlapping | C::Plane};
}

Raster AccurateFractal::draw(const Ifs& ifs, const RenderOptions& options) const {
  check_parameters(*this, options);
  ifs.require_attractor();
  if (ifs.spatial_dims() != 2)
    throw InputError("accurate fractal rendering works on plane tiles; system '" + ifs.name() + "' is not 2D in space");
  const int n = ifs.dim(), ch = n - 2;
  const std::size_t count = ifs.size();
  for (std::size_t k = 0; k < count; ++k) {
    const AffineMap& m = ifs.map(k);
    const double scale = std::max({std::abs(m.a(0, 0)), std::abs(m.a(1, 1)), 1e-300});
    if (std::abs(m.a(0, 1)) > 1e-12 * scale || std::abs(m.a(1, 0)) > 1e-12 * scale)
      throw InputError("accurate fractal rendering supports tile systems, whose maps keep rectangles axis-aligned "
                       "(no rotation or shear); map " + std::to_string(k + 1) + " of '" + ifs.name() + "' rotates or shears");
    for (int c = 2; c < n; ++c)
      if (m.a(0, c) != 0.0 || m.a(1, c) != 0.0)
        throw InputError("accurate fractal rendering: map " + std::to_string(k + 1) + " of '" + ifs.name() +
                         "' moves points by their channel values; tiles need spatial rows that read x and y only");
    if (!(std::abs(m.a(0, 0)) < 1.0 && std::abs(m.a(1, 1)) < 1.0))
      throw InputError("accurate fractal rendering needs contracting tiles: map " + std::to_string(k + 1) + " of '" +
                       ifs.name() + "' does not shrink both sides");
  }
  const Frame frame = Frame::fit(ifs, options.width, options.height, options.window, options.view);
  PieceBudget budget(ifs, frame, 0.25, name());  // tiles split to a quarter pixel
  const std::vector<double>& p = ifs.probabilities();

  // The parent block Q: the fixed point of the box map (exact for rectangle-preserving maps).
  double q[4];
  {
    const Point s = ifs.start_point();
    double box[4] = {s[0], s[0], s[1], s[1]};
    for (int iteration = 0; iteration < 10000; ++iteration) {
      double next[4] = {box[0], box[1], box[2], box[3]};
      for (const AffineMap& m : ifs.maps()) {
        const double xa = m.a(0, 0) * box[0] + m.b(0), xb = m.a(0, 0) * box[1] + m.b(0);
        const double ya = m.a(1, 1) * box[2] + m.b(1), yb = m.a(1, 1) * box[3] + m.b(1);
        next[0] = std::min({next[0], xa, xb});
        next[1] = std::max({next[1], xa, xb});
        next[2] = std::min({next[2], ya, yb});
        next[3] = std::max({next[3], ya, yb});
      }
      const bool same = next[0] == box[0] && next[1] == box[1] && next[2] == box[2] && next[3] == box[3];
      std::copy(next, next + 4, box);
      if (same) break;
    }
    std::copy(box, box + 4, q);
  }
  // Eq. 68: the attractor's centroid (X, Y, G) = integrals of x, y and every channel against
  // the measure (total 1): X = sum p_k ex_k / (1 - sum p_k sx_k), likewise Y, and
  // (I - sum p_k A_gg,k) G = sum p_k (A_gx,k (X, Y) + b_g,k).
  Point centroid{};
  {
    double sx = 0, ex = 0, sy = 0, ey = 0;
    for (std::size_t k = 0; k < count; ++k) {
      sx += p[k] * ifs.map(k).a(0, 0);
      ex += p[k] * ifs.map(k).b(0);
      sy += p[k] * ifs.map(k).a(1, 1);
      ey += p[k] * ifs.map(k).b(1);
    }
    centroid[0] = ex / (1.0 - sx);
    centroid[1] = ey / (1.0 - sy);
    if (ch) {
      std::vector<double> a(ch * ch, 0.0), b(ch, 0.0);
      for (int r = 0; r < ch; ++r) a[r * ch + r] = 1.0;
      for (std::size_t k = 0; k < count; ++k) {
        const AffineMap& m = ifs.map(k);
        for (int r = 0; r < ch; ++r) {
          for (int c = 0; c < ch; ++c) a[r * ch + c] -= p[k] * m.a(2 + r, 2 + c);
          b[r] += p[k] * (m.a(2 + r, 0) * centroid[0] + m.a(2 + r, 1) * centroid[1] + m.b(2 + r));
        }
      }
      const auto g = solve(a, b, ch);
      std::copy(g.begin(), g.end(), centroid.begin() + 2);
    }
  }
  // Eq. 69, composed: the integrals over the tile M(Q) of the piece M(A) are its mass times
  // M(centroid), since the integral of an affine function is the function of the mean.
  auto child = [&](const Tile& t, std::size_t k) {
    Tile c;
    composed::before(t.map, ifs.map(k), n, c.map);  // M o t_k: a sub-tile of M(Q)
    c.mass = t.mass * p[k];
    c.depth = t.depth + 1;
    return c;
  };
  Tile root;
  composed::identity(n, root.map);
  root.mass = 1.0;
  root.depth = 0;
  const double ps = frame.pixel_size(), w = frame.width(), h = frame.height();
  const Window& window = frame.window();
  // M(Q) in pixel coordinates (M keeps rectangles axis-aligned).
  auto pixel_range = [&](const Tile& t, double* lo, double* hi) {
    const double* m = t.map;
    const double xa = m[0] * q[0] + m[n * n], xb = m[0] * q[1] + m[n * n];
    const double ya = m[n + 1] * q[2] + m[n * n + 1], yb = m[n + 1] * q[3] + m[n * n + 1];
    lo[0] = (std::min(xa, xb) - window.xmin) / ps;
    hi[0] = (std::max(xa, xb) - window.xmin) / ps;
    lo[1] = (window.ymax - std::max(ya, yb)) / ps;
    hi[1] = (window.ymax - std::min(ya, yb)) / ps;
  };
  auto off_image = [&](const Tile& t) {
    double lo[2], hi[2];
    pixel_range(t, lo, hi);
    return hi[0] < 0.0 || lo[0] >= w || hi[1] < 0.0 || lo[1] >= h || !(t.mass > 0.0);
  };
  // A tile inside one pixel gives it its integrals exactly; one straddling pixels is split
  // until it is small (1/4 pixel), so the share by area errs only near its edges.
  auto leaf = [&](const Tile& t) {
    double lo[2], hi[2];
    pixel_range(t, lo, hi);
    const bool one_pixel = std::floor(lo[0]) == std::floor(hi[0]) && std::floor(lo[1]) == std::floor(hi[1]);
    return t.depth >= 64 || one_pixel || std::max(hi[0] - lo[0], hi[1] - lo[1]) <= 0.25;
  };
  LeafPlotter plotter(ifs, frame);
  // A leaf's integrals, shared among the pixels it overlaps in proportion to the overlap.
  auto share = [&](LeafPlotter::Batch& batch, const Tile& t) {
    double lo[2], hi[2];
    pixel_range(t, lo, hi);
    const int x0 = std::max(0, static_cast<int>(std::floor(lo[0]))), x1 = std::min(static_cast<int>(w) - 1, static_cast<int>(std::floor(hi[0])));
    const int y0 = std::max(0, static_cast<int>(std::floor(lo[1]))), y1 = std::min(static_cast<int>(h) - 1, static_cast<int>(std::floor(hi[1])));
    const Point mean = composed::apply(t.map, n, centroid);  // the tile's integrals / mass
    double moments[kMaxDim];
    for (int y = y0; y <= y1; ++y) {
      const double fy = hi[1] - lo[1] > 0.0 ? (std::min(hi[1], y + 1.0) - std::max(lo[1], double(y))) / (hi[1] - lo[1])
                                            : (std::floor(lo[1]) == y ? 1.0 : 0.0);
      for (int x = x0; x <= x1; ++x) {
        const double fx = hi[0] - lo[0] > 0.0 ? (std::min(hi[0], x + 1.0) - std::max(lo[0], double(x))) / (hi[0] - lo[0])
                                              : (std::floor(lo[0]) == x ? 1.0 : 0.0);
        const double f = fx * fy;
        if (!(f > 0.0)) continue;
        for (int c = 0; c < ch; ++c) moments[c] = t.mass * f * mean[2 + c];
        plotter.add(batch, static_cast<std::uint32_t>(y * static_cast<int>(w) + x), t.mass * f, moments);
      }
    }
  };
  // The first levels on one thread until there are enough tiles for the jobs.
  std::vector<Tile> level{root}, jobs;
  LeafPlotter::Batch first;
  std::uint64_t operations = 1;
  if (off_image(root)) level.clear();
  if (!level.empty() && leaf(root)) {
    share(first, root);
    level.clear();
  }
  while (!level.empty() && level.size() < 256) {
    std::vector<Tile> next;
    for (const Tile& t : level)
      for (std::size_t k = 0; k < count; ++k) {
        const Tile c = child(t, k);
        ++operations;
        if (off_image(c)) continue;
        if (leaf(c))
          share(first, c);
        else
          next.push_back(c);
      }
    level.swap(next);
  }
  jobs = std::move(level);
  plotter.submit(0, std::move(first));
  std::vector<std::uint64_t> job_operations(jobs.size(), 0);
  parallel_jobs(jobs.size(), options.threads, [&](std::size_t job, int) {
    LeafPlotter::Batch batch;
    std::vector<Tile> stack{jobs[job]};
    std::uint64_t visited = 0, counted = 0;
    while (!stack.empty()) {
      if (visited - counted >= 4096) {
        if (stop_requested()) throw Cancelled();
        budget.spend(visited - counted);
        counted = visited;
      }
      const Tile t = stack.back();
      stack.pop_back();
      for (std::size_t k = 0; k < count; ++k) {
        const Tile c = child(t, k);
        ++visited;
        if (off_image(c)) continue;
        if (leaf(c))
          share(batch, c);
        else
          stack.push_back(c);
      }
    }
    job_operations[job] = visited;
    plotter.submit(job + 1, std::move(batch));
  }, options.progress);
  for (std::uint64_t v : job_operations) operations += v;
  Raster raster = plotter.finish();
  raster.points = operations;
  return raster;
}

}  // namespace ifsforge
