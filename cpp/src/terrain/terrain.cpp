#include "ifsforge/terrain/terrain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/interpolation/grid_recursion.h"
#include "ifsforge/interpolation/vertical_scaling.h"

namespace ifsforge {

std::array<double, 4> Terrain::extent() const {
  if (grid == TerrainGrid::Circular) {
    const double r = radii.empty() ? 0.0 : radii.back();
    return {-r, -r, r, r};
  }
  return {-0.5 * size_x, -0.5 * size_y, 0.5 * size_x, 0.5 * size_y};
}

std::array<double, 3> Terrain::position(int row, int column) const {
  const std::size_t i = std::size_t(row) * columns + column;
  const double h = heights[i];
  if (grid == TerrainGrid::Regular)
    return {(double(column) / (columns - 1) - 0.5) * size_x, (double(row) / (rows - 1) - 0.5) * size_y, h};
  if (grid == TerrainGrid::Irregular) return {(u[i] - 0.5) * size_x, (v[i] - 0.5) * size_y, h};
  // Circular: v runs through the leading circles at v = k / (circles - 1), linearly between them.
  const double k = std::clamp(double(v[i]), 0.0, 1.0) * double(radii.size() - 1);
  const std::size_t lo = std::min<std::size_t>(std::size_t(k), radii.size() - 2);
  const double radius = radii[lo] + (radii[lo + 1] - radii[lo]) * (k - double(lo));
  const double angle = 2.0 * M_PI * double(u[i]);
  return {radius * std::cos(angle), radius * std::sin(angle), h};
}

namespace {

[[noreturn]] void fail(const std::string& what) { throw InputError("terrain: " + what); }

std::vector<double> expand_factors(const std::vector<double>& a22, std::size_t maps, const std::string& what) {
  if (a22.empty()) return std::vector<double>(maps, 0.0);
  std::vector<double> out = a22.size() == 1 ? std::vector<double>(maps, a22[0]) : a22;
  if (out.size() != maps)
    fail(what + " needs " + std::to_string(maps) + " vertical scaling factors (one per map) or one for all, got " +
         std::to_string(a22.size()));
  check_vertical_scaling(out, "terrain: " + what);
  return out;
}

void check_matrix(const std::vector<std::vector<double>>& m, std::size_t rows, std::size_t columns,
                  const std::string& what) {
  if (m.size() != rows) fail(what + " has " + std::to_string(m.size()) + " rows, the heights have " + std::to_string(rows));
  for (std::size_t r = 0; r < rows; ++r) {
    if (m[r].size() != columns)
      fail(what + " row " + std::to_string(r) + " has " + std::to_string(m[r].size()) + " values, expected " +
           std::to_string(columns));
    for (std::size_t c = 0; c < columns; ++c)
      if (!std::isfinite(m[r][c])) fail(what + " [" + std::to_string(r) + "][" + std::to_string(c) + "] is not finite");
  }
}

bool all_zero(const std::vector<std::vector<double>>& m) {
  for (const auto& row : m)
    for (double v : row)
      if (v != 0.0) return false;
  return true;
}

void validate(const TerrainControls& c, int columns, int rows) {
  const bool circular = c.grid == TerrainGrid::Circular;
  const std::size_t cr = c.heights.size(), cc = cr ? c.heights[0].size() : 0;
  if (!circular && (cr < 5 || cc < 5))
    fail(std::string(name_of(c.grid)) + " grids need at least 5 x 5 control heights, got " + std::to_string(cr) +
         " x " + std::to_string(cc));
  if (circular && (cr < 3 || cc < 4))
    fail("circular grids need at least 3 leading circles (the centre included) of 4 control heights, got " +
         std::to_string(cr) + " x " + std::to_string(cc));
  check_matrix(c.heights, cr, cc, "heights");
  for (const auto* shift : {&c.shift_u, &c.shift_v}) {
    const std::string name = shift == &c.shift_u ? "shift_u" : "shift_v";
    if (shift->empty()) continue;
    check_matrix(*shift, cr, cc, name);
    if (c.grid == TerrainGrid::Regular && !all_zero(*shift))
      fail("a regular grid has no displacement (" + name + "); use the irregular grid");
    for (std::size_t r = 0; r < cr; ++r)
      for (std::size_t k = 0; k < cc; ++k) {
        const double s = (*shift)[r][k];
        const std::string at = name + "[" + std::to_string(r) + "][" + std::to_string(k) + "]";
        if (std::fabs(s) >= 0.5) fail(at + " = " + std::to_string(s) + ": a displacement stays below half a control spacing");
        if (s == 0.0) continue;
        if (c.grid == TerrainGrid::Irregular) {
          if (shift == &c.shift_u && (k == 0 || k + 1 == cc))
            fail(at + " must be 0: the first and last columns keep the terrain's outline");
          if (shift == &c.shift_v && (r == 0 || r + 1 == cr))
            fail(at + " must be 0: the first and last rows keep the terrain's outline");
        }
        if (circular && (r == 0 || r + 1 == cr))
          fail(at + " must be 0: the centre and the outer circle stay in place");
      }
  }
  if (circular) {
    if (c.radii.size() != cr)
      fail("a circular grid needs one radius per leading circle: " + std::to_string(cr) + " circles, " +
           std::to_string(c.radii.size()) + " radii");
    if (c.radii[0] != 0.0) fail("radii[0] must be 0: the first leading circle is the centre");
    for (std::size_t k = 1; k < cr; ++k)
      if (!std::isfinite(c.radii[k]) || !(c.radii[k] > c.radii[k - 1]))
        fail("radii must increase strictly, but radii[" + std::to_string(k) + "] = " + std::to_string(c.radii[k]));
    for (std::size_t k = 1; k < cc; ++k)
      if (c.heights[0][k] != c.heights[0][0])
        fail("the centre (radius 0) has one height, but heights[0][" + std::to_string(k) + "] = " +
             std::to_string(c.heights[0][k]) + " differs from heights[0][0] = " + std::to_string(c.heights[0][0]));
  } else if (!c.radii.empty()) {
    fail("radii belong to circular grids");
  }
  if (!(std::isfinite(c.size_x) && c.size_x > 0 && std::isfinite(c.size_y) && c.size_y > 0))
    fail("size_x and size_y must be positive");
  if (columns < 2 || rows < 2 || (circular && columns < 3))
    fail("need at least 2 samples per direction (3 angles on a circle), got " + std::to_string(columns) + " x " +
         std::to_string(rows));
}

/// Step 2 and 3: one leading vector (its control values) interpolated at every sample along it.
/// A circle closes on itself: its data repeats the first value at 360°.
std::vector<double> interpolate_along(const GridRecursion& plan, std::vector<double> values, bool periodic,
                                      const std::vector<double>& a22) {
  if (periodic) values.push_back(values.front());
  std::vector<double> out(plan.samples());
  plan.evaluate(values.data(), a22.data(), out.data());
  if (periodic) out.pop_back();
  return out;
}

/// Step 4: every vertical vector, through the leading vectors' values at its column. The maps
/// of Eq. 94 are linear in the data, so the plan runs on whole row segments at once:
/// row_t = a22_i row_s + v(s) A_i + B_i with A_i, B_i rows made of the leading vectors.
void interpolate_across(const GridRecursion& plan, const std::vector<double>& a22,
                        const std::vector<std::vector<double>>& leading, float* out, std::size_t width, int threads,
                        const ProgressCallback& progress) {
  const std::size_t n = plan.intervals();
  std::vector<std::vector<float>> nodes(n + 1), slope(n), offset(n);
  for (std::size_t j = 0; j <= n; ++j) nodes[j].assign(leading[j].begin(), leading[j].end());
  for (std::size_t i = 0; i < n; ++i) {
    slope[i].resize(width);
    offset[i].resize(width);
    for (std::size_t w = 0; w < width; ++w) {
      // Eq. 94 on [0, 1]: a21_i = F_{i+1} - F_i - a22_i (F_N - F_0), b2_i = F_i - a22_i F_0.
      slope[i][w] = float(leading[i + 1][w] - leading[i][w] - a22[i] * (leading[n][w] - leading[0][w]));
      offset[i][w] = float(leading[i][w] - a22[i] * leading[0][w]);
    }
  }
  // Fixed column blocks: the same arithmetic per element whatever the thread count.
  const std::size_t block = 256, jobs = (width + block - 1) / block;
  parallel_jobs(jobs, threads, [&](std::size_t job, int) {
    const std::size_t w0 = job * block, count = std::min(block, width - w0);
    std::vector<float> sum(count);
    for (const GridRecursion::Op& op : plan.ops()) {
      float* dst = out + std::size_t(op.target) * width + w0;
      switch (op.kind) {
        case GridRecursion::Kind::Node: {
          const float* src = nodes[op.index].data() + w0;
          std::copy(src, src + count, dst);
          break;
        }
        case GridRecursion::Kind::Step: {
          const float* src = out + std::size_t(op.source) * width + w0;
          const float* a = slope[op.map].data() + w0;
          const float* b = offset[op.map].data() + w0;
          const float d = float(a22[op.map]), x = float(plan.position(op.source));
          for (std::size_t w = 0; w < count; ++w) dst[w] = d * src[w] + (x * a[w] + b[w]);
          break;
        }
        case GridRecursion::Kind::Cycle: {
          std::fill(sum.begin(), sum.end(), 0.0f);
          double product = 1.0;
          for (std::uint32_t k = 0; k < op.count && std::fabs(product) > 1e-12; ++k) {
            const GridRecursion::CycleTerm& term = plan.cycle_terms()[op.index + k];
            const float* a = slope[term.map].data() + w0;
            const float* b = offset[term.map].data() + w0;
            const float p = float(product), x = float(plan.position(term.source));
            for (std::size_t w = 0; w < count; ++w) sum[w] += p * (x * a[w] + b[w]);
            product *= a22[term.map];
          }
          const float scale = float(1.0 / (1.0 - product));
          for (std::size_t w = 0; w < count; ++w) dst[w] = sum[w] * scale;
          break;
        }
      }
    }
  }, progress);
}

/// Where sample t of `samples` falls among `controls` control rows: the interval and the fraction.
std::pair<std::size_t, double> locate(std::size_t t, std::size_t samples, std::size_t controls) {
  const double p = double(t) * double(controls - 1) / double(samples - 1);
  const std::size_t k = std::min<std::size_t>(std::size_t(p), controls - 2);
  return {k, p - double(k)};
}

/// Irregular and circular: the cells of the displaced lattice must keep their orientation in
/// parameter space, or the surface would fold over itself.
void check_no_folds(const Terrain& t, std::size_t control_rows, std::size_t control_columns, int threads) {
  const bool periodic = t.grid == TerrainGrid::Circular;
  const std::size_t width = t.columns, cells_across = periodic ? width : width - 1;
  const std::size_t band = 64, jobs = (t.rows - 1 + band - 1) / band;
  std::vector<std::size_t> first(jobs, std::numeric_limits<std::size_t>::max());
  parallel_jobs(jobs, threads, [&](std::size_t job, int) {
    const std::size_t r1 = std::min<std::size_t>((job + 1) * band, t.rows - 1);
    for (std::size_t r = job * band; r < r1; ++r)
      for (std::size_t w = 0; w < cells_across; ++w) {
        const std::size_t w1 = (w + 1) % width;
        const double wrap = w1 < w ? 1.0 : 0.0;  // the circle's last cell closes at 360°
        const std::size_t a = r * width + w, b = r * width + w1, c = (r + 1) * width + w1, d = (r + 1) * width + w;
        auto area = [&](std::size_t p, double pw, std::size_t q, double qw, std::size_t s, double sw) {
          const double ux = t.u[q] + qw - t.u[p] - pw, uy = t.v[q] - t.v[p];
          const double vx = t.u[s] + sw - t.u[p] - pw, vy = t.v[s] - t.v[p];
          return ux * vy - uy * vx;
        };
        if (area(a, 0, b, wrap, c, wrap) <= 0 || area(a, 0, c, wrap, d, 0) <= 0) {
          first[job] = r * width + w;
          return;
        }
      }
  });
  const std::size_t bad = *std::min_element(first.begin(), first.end());
  if (bad == std::numeric_limits<std::size_t>::max()) return;
  const std::size_t r = bad / width, w = bad % width;
  const std::size_t cr = locate(r, t.rows, control_rows).first;
  const std::size_t cc = periodic ? w * control_columns / width : locate(w, width, control_columns).first;
  fail("the displacement folds the grid near control cell (row " + std::to_string(cr) + ", column " +
       std::to_string(cc) + "): use smaller shifts or less displacement roughness");
}

}  // namespace

Terrain make_terrain(const TerrainControls& c, int columns, int rows, int threads, const ProgressCallback& progress) {
  validate(c, columns, rows);
  const bool circular = c.grid == TerrainGrid::Circular;
  const bool displaced = c.grid != TerrainGrid::Regular;
  const std::size_t cr = c.heights.size(), cc = c.heights[0].size();
  const std::size_t maps_u = circular ? cc : cc - 1, maps_v = cr - 1;
  const std::vector<double> a22_u = expand_factors(c.a22_u, maps_u, "a22_u");
  const std::vector<double> a22_v = expand_factors(c.a22_v, maps_v, "a22_v");
  const std::vector<double> a22_shift = expand_factors(c.a22_shift, maps_u, "a22_shift");
  const std::size_t width = columns, height = rows, samples = width * height;
  check_memory(double(samples) * (displaced ? 12.0 : 4.0) + double(cr + 2 * maps_v) * width * 12.0 + 64.0 * height,
               "a " + std::to_string(columns) + " x " + std::to_string(rows) + " terrain");

  Terrain t;
  t.grid = c.grid;
  t.columns = columns;
  t.rows = rows;
  t.size_x = c.size_x;
  t.size_y = c.size_y;
  t.radii = c.radii;

  // Step 2: the leading vectors (a circle is sampled at `columns` angles plus 360°).
  const GridRecursion along(maps_u, circular ? width + 1 : width);
  std::vector<std::vector<double>> leading(cr);
  for (std::size_t r = 0; r < cr; ++r) leading[r] = interpolate_along(along, c.heights[r], circular, a22_u);

  // Step 4 for the heights: every vertical (radial) vector across the leading vectors.
  // Faulted in on every core, huge pages where the kernel gives them, before the one-thread zeroing.
  resize_large(t.heights, samples);
  interpolate_across(GridRecursion(maps_v, height), a22_v, leading, t.heights.data(), width, threads, progress);

  if (displaced) {
    // Step 3: the displacement of each leading vector, at the same samples; across the
    // leading vectors the displaced positions vary linearly.
    const std::vector<std::vector<double>> zero(cr, std::vector<double>(cc, 0.0));
    const auto& su = c.shift_u.empty() ? zero : c.shift_u;
    const auto& sv = c.shift_v.empty() ? zero : c.shift_v;
    std::vector<std::vector<double>> lead_u(cr), lead_v(cr);
    for (std::size_t r = 0; r < cr; ++r) {
      lead_u[r] = interpolate_along(along, su[r], circular, a22_shift);
      lead_v[r] = interpolate_along(along, sv[r], circular, a22_shift);
    }
    resize_large(t.u, samples);
    resize_large(t.v, samples);
    const double spacing_u = 1.0 / double(maps_u), spacing_v = 1.0 / double(maps_v);
    const std::size_t band = 64, jobs = (height + band - 1) / band;
    parallel_jobs(jobs, threads, [&](std::size_t job, int) {
      for (std::size_t row = job * band; row < std::min(height, (job + 1) * band); ++row) {
        const auto [k, f] = locate(row, height, cr);
        const double v0 = double(row) / double(height - 1);
        for (std::size_t w = 0; w < width; ++w) {
          const double u0 = circular ? double(w) / double(width) : double(w) / double(width - 1);
          const double du = (1.0 - f) * lead_u[k][w] + f * lead_u[k + 1][w];
          const double dv = (1.0 - f) * lead_v[k][w] + f * lead_v[k + 1][w];
          t.u[row * width + w] = float(u0 + du * spacing_u);
          t.v[row * width + w] = float(v0 + dv * spacing_v);
        }
      }
    });
    check_no_folds(t, cr, cc, threads);
  }
  const auto [lo, hi] = std::minmax_element(t.heights.begin(), t.heights.end());
  t.min_height = *lo;
  t.max_height = *hi;
  return t;
}

}  // namespace ifsforge
