#include "ifsforge/geometry/triangle_mesh.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {

void compute_normals(TriangleMesh& mesh, const ProgressCallback& progress) {
  // Angle-weighted (Thurmer & Wuthrich): independent of how faces are triangulated.
  const auto& positions = mesh.positions;
  const auto& triangles = mesh.triangles;
  const std::size_t count = positions.size();
  mesh.normals.assign(count, {0.0f, 0.0f, 0.0f});
  auto sub = [](const std::array<float, 3>& a, const std::array<float, 3>& b) {
    return std::array<double, 3>{double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]};
  };
  auto length = [](const std::array<double, 3>& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
  // Each job owns a block of vertices and adds, in triangle order, the corners of its own
  // vertices only: every vertex sums the same terms in the same order whatever the blocks, so the
  // normals are those of one thread for any thread count. A job reads every triangle's indices,
  // so there are as many jobs as threads.
  const std::size_t jobs = std::max<std::size_t>(1, std::min<std::size_t>(resolve_threads(0), count / 1024));
  parallel_jobs(jobs, 0, [&](std::size_t job, int) {
    const std::uint32_t lo = static_cast<std::uint32_t>(count * job / jobs);
    const std::uint32_t hi = static_cast<std::uint32_t>(count * (job + 1) / jobs);
    auto mine = [&](std::uint32_t v) { return v >= lo && v < hi; };
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      if ((i & 0xFFFF) == 0 && stop_requested()) throw Cancelled();
      const auto& t = triangles[i];
      if (!mine(t[0]) && !mine(t[1]) && !mine(t[2])) continue;
      const auto& a = positions[t[0]];
      const auto u = sub(positions[t[1]], a), v = sub(positions[t[2]], a);
      std::array<double, 3> n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
      const double area2 = length(n);
      if (area2 == 0.0) continue;
      for (double& x : n) x /= area2;
      for (int corner = 0; corner < 3; ++corner) {
        if (!mine(t[corner])) continue;
        const auto& p = positions[t[corner]];
        const auto e1 = sub(positions[t[(corner + 1) % 3]], p), e2 = sub(positions[t[(corner + 2) % 3]], p);
        const double cosine = (e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]) / (length(e1) * length(e2));
        const double angle = std::acos(std::clamp(cosine, -1.0, 1.0));
        for (int k = 0; k < 3; ++k) mesh.normals[t[corner]][k] += static_cast<float>(angle * n[k]);
      }
    }
    for (std::uint32_t v = lo; v < hi; ++v) {
      auto& n = mesh.normals[v];
      const float l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (l > 0)
        for (float& c : n) c /= l;
    }
  }, progress);
}

}  // namespace ifsforge
