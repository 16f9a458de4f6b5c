#pragma once
/// @file Maps from meaningful quantities (seed Eq. 5 and its 3D analogue) and back, so that
/// user interfaces edit scale, rotation, shear, reflection and translation.
#include <array>

#include "ifsforge/model/affine_map.h"

namespace ifsforge {

/// 2D: A = [[Mx cos tx, -My sin ty], [Mx sin tx, My cos ty]] . [[1, h], [0, 1]] . F   (Eq. 5)
/// 3D: A = Rz(rz) Ry(ry) Rx(rx) . diag(M) . [[1, hxy, hxz], [0, 1, hyz], [0, 0, 1]] . F
/// where F = diag(+-1) holds the reflections. Angles are in degrees.
struct MapParams {
  int dim = 2;                                ///< 2 or 3 (the spatial dimensions)
  std::array<double, 3> scale{1, 1, 1};       ///< Mx, My, Mz
  std::array<double, 3> rotation{0, 0, 0};    ///< 2D: theta_x, theta_y; 3D: rx, ry, rz
  std::array<double, 3> shear{0, 0, 0};       ///< 2D: h; 3D: hxy, hxz, hyz
  std::array<bool, 3> reflect{false, false, false};
  std::array<double, 3> translation{0, 0, 0};
};

/// @brief The spatial map described by `params` (dimension params.dim).
AffineMap map_from_params(const MapParams& params);

/// @brief Parameters reproducing the leading 2x2 or 3x3 block and offset of `map`
/// (QR decomposition; 2D angles come out with theta_x == theta_y).
MapParams params_from_map(const AffineMap& map, int spatial_dims);

}  // namespace ifsforge
