#include "ifsforge/model/map_params.h"

#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/model/linear_algebra.h"

namespace ifsforge {
namespace {

constexpr double kDegree = M_PI / 180.0;

la::Matrix upper_factor(const MapParams& p, int n) {
  // diag(M) . Shear . F, the upper-triangular factor shared by 2D and 3D.
  la::Matrix u{};
  const double h[3][3] = {{1, p.shear[0], p.shear[1]}, {0, 1, n == 2 ? 0 : p.shear[2]}, {0, 0, 1}};
  for (int r = 0; r < n; ++r)
    for (int c = r; c < n; ++c) u[r][c] = p.scale[r] * h[r][c] * (p.reflect[c] ? -1.0 : 1.0);
  return u;
}

la::Matrix rotation_3d(double rx, double ry, double rz) {
  const double cx = std::cos(rx), sx = std::sin(rx), cy = std::cos(ry), sy = std::sin(ry),
               cz = std::cos(rz), sz = std::sin(rz);
  la::Matrix r{};  // Rz . Ry . Rx
  r[0] = {cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx};
  r[1] = {sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx};
  r[2] = {-sy, cy * sx, cy * cx};
  return r;
}

}  // namespace

AffineMap map_from_params(const MapParams& p) {
  const int n = p.dim;
  if (n != 2 && n != 3) throw InputError("map parameters describe 2D or 3D maps only");
  la::Matrix rot{};
  if (n == 2) {
    // Eq. 5 with unit scales: the columns are the rotated x and y axes.
    const double tx = p.rotation[0] * kDegree, ty = p.rotation[1] * kDegree;
    rot[0] = {std::cos(tx), -std::sin(ty)};
    rot[1] = {std::sin(tx), std::cos(ty)};
  } else {
    rot = rotation_3d(p.rotation[0] * kDegree, p.rotation[1] * kDegree, p.rotation[2] * kDegree);
  }
  const la::Matrix u = upper_factor(p, n);
  AffineMap map(n);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      double v = 0.0;
      for (int k = 0; k < n; ++k) v += rot[r][k] * u[k][c];
      map.a(r, c) = v;
    }
    map.b(r) = p.translation[r];
  }
  if (!map.finite()) throw InputError("map parameters are not finite numbers");
  return map;
}

MapParams params_from_map(const AffineMap& map, int n) {
  if (n != 2 && n != 3) throw InputError("map parameters describe 2D or 3D maps only");
  if (map.dim() < n) throw InputError("the map has fewer dimensions than asked for");
  la::Matrix q, r;
  la::qr(la::block(map, n), n, q, r);
  MapParams p;
  p.dim = n;
  for (int i = 0; i < n; ++i) p.translation[i] = map.b(i);
  p.reflect[n - 1] = r[n - 1][n - 1] < 0.0;
  for (int i = 0; i < n; ++i) p.scale[i] = std::abs(r[i][i]);
  auto shear = [&](int row, int col) {
    const double f = p.reflect[col] ? -1.0 : 1.0;
    return p.scale[row] > 1e-15 ? r[row][col] / (p.scale[row] * f) : 0.0;
  };
  if (n == 2) {
    double theta = std::atan2(q[1][0], q[0][0]);
    if (p.scale[0] <= 1e-15) {
      // First column zero: put the second column on the rotated y axis instead.
      const double a12 = map.a(0, 1), a22 = map.a(1, 1);
      theta = std::atan2(-a12, a22);
      p.scale[1] = std::hypot(a12, a22);
      p.reflect[1] = false;
    }
    p.rotation = {theta / kDegree, theta / kDegree, 0.0};
    p.shear = {shear(0, 1), 0.0, 0.0};
  } else {
    double rx, ry, rz;
    if (std::abs(q[2][0]) < 1.0 - 1e-12) {
      ry = std::asin(-q[2][0]);
      rx = std::atan2(q[2][1], q[2][2]);
      rz = std::atan2(q[1][0], q[0][0]);
    } else {  // gimbal lock: rx and rz turn about the same axis
      ry = q[2][0] < 0 ? M_PI / 2 : -M_PI / 2;
      rx = 0.0;
      rz = std::atan2(-q[0][1], q[1][1]);
    }
    p.rotation = {rx / kDegree, ry / kDegree, rz / kDegree};
    p.shear = {shear(0, 1), shear(0, 2), shear(1, 2)};
  }
  return p;
}

}  // namespace ifsforge
