#include "ifsforge/terrain/terrain_mesh.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "terrain_cells.h"

namespace ifsforge {
namespace {

using Vec = std::array<double, 3>;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

std::array<float, 3> point(const Vec& p) { return {float(p[0]), float(p[1]), float(p[2])}; }

std::array<float, 3> unit(const Vec& n) {
  const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  return point(l > 0 ? Vec{n[0] / l, n[1] / l, n[2] / l} : Vec{0, 0, 1});
}

}  // namespace

TriangleMesh terrain_mesh(const Terrain& t, const TerrainMeshOptions& o, int threads) {
  if (t.columns < 2 || t.rows < 2 || t.heights.size() != std::size_t(t.columns) * t.rows)
    throw InputError("terrain mesh: the terrain has no samples");
  const bool circular = t.grid == TerrainGrid::Circular;
  const std::size_t w = t.columns, h = t.rows;
  const std::size_t surface = circular ? 1 + w * (h - 1) : w * h;
  // The outline, counter-clockwise seen from above, as lattice (row, column) pairs.
  std::vector<std::pair<std::size_t, std::size_t>> outline;
  if (o.solid) {
    if (circular) {
      for (std::size_t c = 0; c < w; ++c) outline.push_back({h - 1, c});
    } else {
      for (std::size_t c = 0; c + 1 < w; ++c) outline.push_back({0, c});
      for (std::size_t r = 0; r + 1 < h; ++r) outline.push_back({r, w - 1});
      for (std::size_t c = w - 1; c > 0; --c) outline.push_back({h - 1, c});
      for (std::size_t r = h - 1; r > 0; --r) outline.push_back({r, 0});
    }
  }
  const std::size_t vertices = surface + (o.solid ? outline.size() + 1 : 0);
  const std::size_t across = detail::cells_across(t);
  // Two triangles per cell, except the centre cells of a circle, which collapse to one.
  const std::size_t surface_triangles = 2 * across * (h - 1) - (circular ? w : 0);
  const std::size_t triangles = surface_triangles + (o.solid ? 3 * outline.size() : 0);
  check_memory(double(vertices) * 60.0 + double(triangles) * 12.0,
               "a terrain mesh of " + std::to_string(vertices) + " vertices");
  if (vertices >= 0xFFFFFFFFull) throw InputError("terrain mesh: too many vertices for 32-bit indices");

  // Large arrays: huge pages, faulted in on every core (a 1024² mesh is 130 MB).
  TriangleMesh mesh;
  resize_large(mesh.positions, vertices);
  resize_large(mesh.normals, vertices);
  resize_large(mesh.uvs, vertices);
  if (!o.palette.colors.empty()) resize_large(mesh.colors, vertices);
  reserve_large(mesh.triangles, triangles);  // a solid's walls and floor follow the surface
  mesh.triangles.resize(surface_triangles);
  const double lo = t.min_height, range = double(t.max_height) - t.min_height;
  auto index = [&](std::size_t sample) -> std::uint32_t {
    const std::size_t r = sample / w, c = sample % w;
    if (!circular) return std::uint32_t(sample);
    return std::uint32_t(r == 0 ? 0 : 1 + (r - 1) * w + c);
  };
  auto set_vertex = [&](std::size_t i, const Vec& p, const Vec& normal) {
    mesh.positions[i] = point(p);
    mesh.normals[i] = unit(normal);
    const float level = range > 0 ? float((p[2] - lo) / range) : 0.0f;
    mesh.uvs[i] = {std::clamp(level, 0.0f, 1.0f), 0.5f};
    if (!mesh.colors.empty()) {
      const auto rgb = o.palette.lookup(level);
      mesh.colors[i] = {rgb[0], rgb[1], rgb[2], 1.0f};
    }
  };

  const std::size_t band = 32, jobs = (h + band - 1) / band;
  parallel_jobs(jobs, threads, [&](std::size_t job, int) {
    for (std::size_t r = job * band; r < std::min(h, (job + 1) * band); ++r) {
      if (circular && r == 0) {
        // The centre: the mean orientation of the fan around it.
        const Vec centre = t.position(0, 0);
        Vec n{0, 0, 0};
        for (std::size_t c = 0; c < w; ++c) {
          const Vec k = cross(sub(t.position(1, c), centre), sub(t.position(1, (c + 1) % w), centre));
          for (int i = 0; i < 3; ++i) n[i] += k[i];
        }
        set_vertex(0, centre, n);
        continue;
      }
      for (std::size_t c = 0; c < w; ++c) {
        // Central differences on the lattice (one-sided on the outline; a circle wraps).
        const std::size_t cl = circular ? (c + w - 1) % w : (c > 0 ? c - 1 : c);
        const std::size_t cr = circular ? (c + 1) % w : std::min(c + 1, w - 1);
        const std::size_t rl = r > 0 ? r - 1 : r, rr = std::min(r + 1, h - 1);
        const Vec du = sub(t.position(int(r), int(cr)), t.position(int(r), int(cl)));
        const Vec dv = sub(t.position(int(rr), int(c)), t.position(int(rl), int(c)));
        Vec n = cross(du, dv);
        if (circular) n = {-n[0], -n[1], -n[2]};  // u counter-clockwise, v outwards: du x dv points down
        set_vertex(index(r * w + c), t.position(int(r), int(c)), n);
      }
    }
    // The triangles of this band's cells, at offsets known in advance.
    for (std::size_t r = job * band; r < std::min(h - 1, (job + 1) * band); ++r) {
      std::size_t k = circular ? (r == 0 ? 0 : w + 2 * across * (r - 1)) : 2 * across * r;
      for (std::size_t c = 0; c < across; ++c)
        for (const auto& tri : detail::cell_triangles(t, r, c)) {
          const std::array<std::uint32_t, 3> v = {index(tri[0]), index(tri[1]), index(tri[2])};
          if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;  // collapsed onto the centre
          mesh.triangles[k++] = v;
        }
    }
  });

  if (o.solid) {
    const std::array<double, 4> box = t.extent();
    const double margin = std::max(0.1 * range, 0.01 * std::max(box[2] - box[0], box[3] - box[1]));
    const double base = std::isnan(o.base) ? lo - margin : o.base;
    if (!std::isfinite(base) || base >= lo)
      throw InputError("terrain mesh: the floor of a solid must lie below the lowest point (" + std::to_string(lo) + ")");
    const std::size_t m = outline.size(), floor = surface, centre = surface + m;
    for (std::size_t k = 0; k < m; ++k) {
      const Vec p = t.position(int(outline[k].first), int(outline[k].second));
      set_vertex(floor + k, {p[0], p[1], base}, {p[0], p[1], 0.0});
    }
    set_vertex(centre, {0.0, 0.0, base}, {0.0, 0.0, -1.0});
    for (std::size_t k = 0; k < m; ++k) {
      const std::uint32_t a = index(outline[k].first * w + outline[k].second);
      const std::uint32_t b = index(outline[(k + 1) % m].first * w + outline[(k + 1) % m].second);
      const std::uint32_t fa = std::uint32_t(floor + k), fb = std::uint32_t(floor + (k + 1) % m);
      mesh.triangles.push_back({a, fa, fb});  // the wall, facing outwards
      mesh.triangles.push_back({a, fb, b});
      mesh.triangles.push_back({std::uint32_t(centre), fb, fa});  // the floor, facing down
    }
  }
  return mesh;
}

}  // namespace ifsforge
