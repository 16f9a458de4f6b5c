#include "ifsforge/render/escape_time.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {
namespace {

/// The parallelogram {c + s u + t v : |s|, |t| <= 1}.
struct Region {
  double cx, cy, ux, uy, vx, vy;
};

/// Separating-axis test: the edge normals of both parallelograms (a segment or a point is a
/// degenerate parallelogram whose zero edges give no axis).
bool overlap(const Region& a, const Region& b) {
  const double dx = a.cx - b.cx, dy = a.cy - b.cy;
  const double axes[4][2] = {{-a.uy, a.ux}, {-a.vy, a.vx}, {-b.uy, b.ux}, {-b.vy, b.vx}};
  for (const auto& n : axes) {
    if (n[0] == 0.0 && n[1] == 0.0) continue;
    const double ra = std::abs(a.ux * n[0] + a.uy * n[1]) + std::abs(a.vx * n[0] + a.vy * n[1]);
    const double rb = std::abs(b.ux * n[0] + b.uy * n[1]) + std::abs(b.vx * n[0] + b.vy * n[1]);
    if (std::abs(dx * n[0] + dy * n[1]) > ra + rb) return false;
  }
  return true;
}

/// The attractor's hull as a discrete oriented polytope: slabs lo_k <= n_k . x <= hi_k for 12
/// directions 15 degrees apart (edges of triangles, squares and hexagons among them), and the
/// polygon they bound. Much tighter than a box, so escaping branches are cut sooner.
struct Hull {
  static constexpr int kAxes = 12;
  double nx[kAxes], ny[kAxes], lo[kAxes], hi[kAxes];
  std::vector<std::array<double, 2>> polygon;
};

Hull hull_of(const Ifs& ifs) {
  Hull h;
  for (int k = 0; k < Hull::kAxes; ++k) {
    h.nx[k] = std::cos(k * M_PI / Hull::kAxes);
    h.ny[k] = std::sin(k * M_PI / Hull::kAxes);
    h.lo[k] = INFINITY;
    h.hi[k] = -INFINITY;
  }
  sample_attractor(ifs, 1u << 17, 0xE7A, [&](const Point& p) {
    for (int k = 0; k < Hull::kAxes; ++k) {
      const double d = h.nx[k] * p[0] + h.ny[k] * p[1];
      h.lo[k] = std::min(h.lo[k], d);
      h.hi[k] = std::max(h.hi[k], d);
    }
  });
  // The sample may miss the far tips: widen every slab by 2% of the widest.
  double widest = 0.0;
  for (int k = 0; k < Hull::kAxes; ++k) widest = std::max(widest, h.hi[k] - h.lo[k]);
  const double margin = 0.02 * widest + 1e-12;
  for (int k = 0; k < Hull::kAxes; ++k) {
    h.lo[k] -= margin;
    h.hi[k] += margin;
  }
  // The polygon: a large square clipped by every half-plane (Sutherland-Hodgman).
  const double c = 0.5 * (h.lo[0] + h.hi[0]), d = 0.5 * (h.lo[Hull::kAxes / 2] + h.hi[Hull::kAxes / 2]);
  const double big = 4.0 * widest + 1.0;
  h.polygon = {{c - big, d - big}, {c + big, d - big}, {c + big, d + big}, {c - big, d + big}};
  auto clip = [&](double nx, double ny, double limit) {  // keep n . x <= limit
    std::vector<std::array<double, 2>> out;
    for (std::size_t i = 0; i < h.polygon.size(); ++i) {
      const auto& a = h.polygon[i];
      const auto& b = h.polygon[(i + 1) % h.polygon.size()];
      const double da = nx * a[0] + ny * a[1] - limit, db = nx * b[0] + ny * b[1] - limit;
      if (da <= 0.0) out.push_back(a);
      if ((da < 0.0) != (db < 0.0) && da != db) {
        const double t = da / (da - db);
        out.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])});
      }
    }
    h.polygon.swap(out);
  };
  for (int k = 0; k < Hull::kAxes; ++k) {
    clip(h.nx[k], h.ny[k], h.hi[k]);
    clip(-h.nx[k], -h.ny[k], -h.lo[k]);
  }
  return h;
}

/// Separating-axis test of a parallelogram against the hull: its slabs, then the
/// parallelogram's own edge normals against the polygon.
bool overlap(const Region& q, const Hull& h) {
  for (int k = 0; k < Hull::kAxes; ++k) {
    const double c = h.nx[k] * q.cx + h.ny[k] * q.cy;
    const double r = std::abs(h.nx[k] * q.ux + h.ny[k] * q.uy) + std::abs(h.nx[k] * q.vx + h.ny[k] * q.vy);
    if (c + r < h.lo[k] || c - r > h.hi[k]) return false;
  }
  const double axes[2][2] = {{-q.uy, q.ux}, {-q.vy, q.vx}};
  for (const auto& n : axes) {
    if (n[0] == 0.0 && n[1] == 0.0) continue;
    const double c = n[0] * q.cx + n[1] * q.cy;
    const double r = std::abs(n[0] * q.ux + n[1] * q.uy) + std::abs(n[0] * q.vx + n[1] * q.vy);
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& v : h.polygon) {
      const double d = n[0] * v[0] + n[1] * v[1];
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    if (c + r < lo || c - r > hi) return false;
  }
  return true;
}

/// True when the hull's polygon lies inside the parallelogram q.
bool contains(const Region& q, const Hull& h) {
  const double det = q.ux * q.vy - q.vx * q.uy;
  if (det == 0.0) return false;
  for (const auto& v : h.polygon) {
    const double x = v[0] - q.cx, y = v[1] - q.cy;
    const double s = (x * q.vy - q.vx * y) / det, t = (q.ux * y - x * q.uy) / det;
    if (std::abs(s) > 1.0 || std::abs(t) > 1.0) return false;
  }
  return true;
}

/// True when the point (x, y) lies in the parallelogram q.
bool inside(const Region& q, double x, double y) {
  const double det = q.ux * q.vy - q.vx * q.uy;
  if (det == 0.0) return false;
  x -= q.cx;
  y -= q.cy;
  const double s = (x * q.vy - q.vx * y) / det, t = (q.ux * y - x * q.uy) / det;
  return std::abs(s) <= 1.0 && std::abs(t) <= 1.0;
}

struct InverseMap {
  bool invertible;
  double a, b, c, d, e, f;  ///< f_j(x) = [[a, b], [c, d]] x + (e, f)
  Region image_of_box;      ///< w_j(B), for maps with no inverse
};

struct Node {
  Region q;
  int depth;
  std::uint32_t map;  ///< the map whose inverse made this node (the address digit)
};

}  // namespace

Capabilities EscapeTime::capabilities() const {
  // Inverse maps on pixels; C would need its own escape test.
  using C = Capabilities;
  return {C::AverageContractive | C::Overlapping | C::Plane};
}

Raster EscapeTime::draw(const Ifs& ifs, const RenderOptions& options) const {
  const ParameterValues params(*this, options);
  const PixelSpace space = make_pixel_space(ifs, options, name());
  if (space.spatial_reads_channels)
    throw InputError("escape time inverts the spatial maps, so their rows must not read the color channels (system '" +
                     ifs.name() + "')");
  const bool linear = params.choice("norm", {"euclidean", "linear"}) == "linear";
  const bool smallest_first = params.choice("rule", {"min", "max"}) == "min";
  const int max_depth = static_cast<int>(params.integer("iterations", 1, 100000));
  const bool escape_image = params.choice("output", {"attractor", "escape-time"}) == "escape-time";
  check_memory(space.pixels() * (4.0 + 4.0 * space.channels), "an escape-time image");

  // H: a polygon holding the attractor; its bounding box stands in for it under maps with no inverse.
  const Hull hull = hull_of(ifs);
  double bx0 = INFINITY, bx1 = -INFINITY, by0 = INFINITY, by1 = -INFINITY;
  for (const auto& v : hull.polygon) {
    bx0 = std::min(bx0, v[0]);
    bx1 = std::max(bx1, v[0]);
    by0 = std::min(by0, v[1]);
    by1 = std::max(by1, v[1]);
  }
  const Region box{0.5 * (bx0 + bx1), 0.5 * (by0 + by1), 0.5 * (bx1 - bx0), 0.0, 0.0, 0.5 * (by1 - by0)};
  // Points known to lie on the attractor: an image holding one proves the pixel covered (and
  // ends branches that keep touching the attractor at a vertex without ever swallowing H).
  std::vector<Point> known;
  for (const Point& p : ifs.fixed_points())
    if (std::isfinite(p[0]) && std::isfinite(p[1])) known.push_back(p);
  const std::size_t fixed = known.size();
  sample_attractor(ifs, 64, 0xA77, [&](const Point& p) { known.push_back(p); });
  const double large = 4.0 * box.ux * box.vy / 1024.0;  // regions this big test the sample too
  const double huge_area = 64.0 * 4.0 * box.ux * box.vy;
  auto known_point_in = [&](const Region& q) -> int {
    const bool big = 4.0 * std::abs(q.ux * q.vy - q.vx * q.uy) >= large;
    for (std::size_t k = 0; k < (big ? known.size() : fixed); ++k)
      if (inside(q, known[k][0], known[k][1])) return static_cast<int>(k);
    return -1;
  };
  const std::size_t n = ifs.size();
  std::vector<InverseMap> inverse(n);
  for (std::size_t j = 0; j < n; ++j) {
    const AffineMap& w = ifs.map(j);
    const double a = w.a(0, 0), b = w.a(0, 1), c = w.a(1, 0), d = w.a(1, 1);
    const double det = a * d - b * c, scale = std::max({std::abs(a), std::abs(b), std::abs(c), std::abs(d)});
    InverseMap& f = inverse[j];
    f.invertible = std::abs(det) > 1e-12 * scale * scale;
    if (f.invertible) {
      f.a = d / det;
      f.b = -b / det;
      f.c = -c / det;
      f.d = a / det;
      f.e = -(f.a * w.b(0) + f.b * w.b(1));
      f.f = -(f.c * w.b(0) + f.d * w.b(1));
    }
    f.image_of_box = {a * box.cx + b * box.cy + w.b(0), c * box.cx + d * box.cy + w.b(1),
                      a * box.ux, c * box.ux, b * box.vy, d * box.vy};
  }
  const Point start = ifs.start_point();
  const Frame& frame = space.frame;
  const double ps = frame.pixel_size();
  Raster raster = empty_raster(ifs, space);
  const int channels = space.channels;
  constexpr std::size_t kNodeBudget = 1u << 18;  // per pixel; beyond it the pixel counts as covered
  constexpr int kRowsPerJob = 8;
  const std::size_t jobs = (space.height + kRowsPerJob - 1) / kRowsPerJob;
  std::vector<std::uint64_t> job_operations(jobs, 0);
  parallel_jobs(jobs, options.threads, [&](std::size_t job, int) {
    std::vector<Node> stack;
    std::vector<std::uint32_t> path;  // address of the node being expanded (outermost first)
    std::uint64_t operations = 0;
    for (int y = static_cast<int>(job) * kRowsPerJob; y < std::min(space.height, static_cast<int>(job + 1) * kRowsPerJob); ++y)
      for (int x = 0; x < space.width; ++x) {
        const Region pixel{frame.window().xmin + (x + 0.5) * ps, frame.window().ymax - (y + 0.5) * ps,
                           0.5 * ps, 0.0, 0.0, 0.5 * ps};
        int deepest = 0;
        bool covered = false;
        std::size_t nodes = 0;
        std::uint32_t final_map = 0;
        bool via_singular = false;
        int witness = -1;  // index of the known attractor point that proved the pixel covered
        stack.clear();
        path.clear();
        if (overlap(pixel, hull)) stack.push_back({pixel, 0, 0});
        while (!stack.empty() && !covered) {
          const Node node = stack.back();
          stack.pop_back();
          path.resize(node.depth > 0 ? node.depth - 1 : 0);
          if (node.depth > 0) path.push_back(node.map);
          deepest = std::max(deepest, node.depth);
          witness = known_point_in(node.q);
          // An image that has grown far beyond H while still touching it is not resolved by
          // going deeper (image and distance grow alike): the pixel lies within a fraction of
          // a pixel of a piece of the attractor, and counts as covered.
          const bool huge = 4.0 * std::abs(node.q.ux * node.q.vy - node.q.vx * node.q.uy) > huge_area;
          if (witness >= 0 || contains(node.q, hull) || huge || node.depth >= max_depth || ++nodes > kNodeBudget) {
            covered = true;
            break;
          }
          // Children in the order of Eq. 55-56.
          std::pair<double, Node> children[kMaxDim * 4];
          int count = 0;
          for (std::size_t j = 0; j < n && !covered; ++j) {
            const InverseMap& f = inverse[j];
            if (!f.invertible) {
              if (overlap(node.q, f.image_of_box)) {
                covered = via_singular = true;
                final_map = static_cast<std::uint32_t>(j);
              }
              continue;
            }
            const Region& q = node.q;
            const Region child{f.a * q.cx + f.b * q.cy + f.e, f.c * q.cx + f.d * q.cy + f.f,
                               f.a * q.ux + f.b * q.uy, f.c * q.ux + f.d * q.uy,
                               f.a * q.vx + f.b * q.vy, f.c * q.vx + f.d * q.vy};
            ++operations;
            if (!overlap(child, hull)) continue;
            const double dx = child.cx - q.cx, dy = child.cy - q.cy;
            const double delta = linear ? std::abs(dx) + std::abs(dy) : std::sqrt(dx * dx + dy * dy);
            if (count < kMaxDim * 4) children[count++] = {delta, Node{child, node.depth + 1, static_cast<std::uint32_t>(j)}};
          }
          if (covered) break;
          std::stable_sort(children, children + count, [&](const auto& l, const auto& r) {
            return smallest_first ? l.first < r.first : l.first > r.first;
          });
          for (int k = count - 1; k >= 0; --k) stack.push_back(children[k].second);  // preferred on top
        }
        const std::size_t pixel_index = std::size_t(y) * space.width + x;
        if (covered) {
          raster.density[pixel_index] = escape_image ? static_cast<float>(max_depth + 1) : 1.0f;
          if (channels) {
            // A point of the attractor in the pixel: w_path (x*), x* the known point the last
            // image held, or the start point (on A, inside H).
            Point p = witness >= 0 ? known[witness] : start;
            if (via_singular) p = ifs.map(final_map)(p);
            for (auto it = path.rbegin(); it != path.rend(); ++it) p = ifs.map(*it)(p);
            for (int c = 0; c < channels; ++c) raster.channels[pixel_index * channels + c] = static_cast<float>(p[2 + c]);
          }
        } else if (escape_image) {
          raster.density[pixel_index] = static_cast<float>(deepest + 1);
        }
      }
    job_operations[job] = operations;
  }, options.progress);
  for (std::uint64_t o : job_operations) raster.points += o;
  return raster;
}

}  // namespace ifsforge
