#include "ifsforge/geometry/triangle_mesh.h"

#include <algorithm>
#include <cmath>

namespace ifsforge {

void compute_normals(TriangleMesh& mesh) {
  // Angle-weighted (Thurmer & Wuthrich): independent of how faces are triangulated.
  mesh.normals.assign(mesh.positions.size(), {0.0f, 0.0f, 0.0f});
  auto sub = [](const std::array<float, 3>& a, const std::array<float, 3>& b) {
    return std::array<double, 3>{double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]};
  };
  auto length = [](const std::array<double, 3>& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
  for (const auto& t : mesh.triangles) {
    const auto& a = mesh.positions[t[0]];
    const auto& b = mesh.positions[t[1]];
    const auto& c = mesh.positions[t[2]];
    const auto u = sub(b, a), v = sub(c, a);
    std::array<double, 3> n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double area2 = length(n);
    if (area2 == 0.0) continue;
    for (double& x : n) x /= area2;
    for (int corner = 0; corner < 3; ++corner) {
      const auto& p = mesh.positions[t[corner]];
      const auto e1 = sub(mesh.positions[t[(corner + 1) % 3]], p), e2 = sub(mesh.positions[t[(corner + 2) % 3]], p);
      const double cosine = (e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]) / (length(e1) * length(e2));
      const double angle = std::acos(std::clamp(cosine, -1.0, 1.0));
      for (int k = 0; k < 3; ++k) mesh.normals[t[corner]][k] += static_cast<float>(angle * n[k]);
    }
  }
  for (auto& n : mesh.normals) {
    const float l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (l > 0)
      for (float& c : n) c /= l;
  }
}

}  // namespace ifsforge
