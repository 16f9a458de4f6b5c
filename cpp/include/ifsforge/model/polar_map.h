#pragma once
/// @file Polar IFS maps (seed 3.3.3, Eq. 30-32): maps locally contractive about a point.
#include <array>
#include <string>
#include <vector>

#include "ifsforge/model/affine_map.h"

namespace ifsforge {

/// A map of the plane written in polar coordinates about its centre P (Eq. 31,
/// PM = (rho cos theta, rho sin theta)) by two functions F and G (Eq. 32):
///   rho'   = rho (tanh(k F(rho, theta)) + 1) / 2,
///   theta' = G(rho, theta),
/// with the family
///   F(rho, theta) = f0 + f1 tanh(rho) + f2 cos theta + f3 sin theta + f4 cos 2theta + f5 sin 2theta,
///   G(rho, theta) = w theta + g0 + g1 rho + g2 cos theta + g3 sin theta   (w: the winding).
/// F is bounded (tanh bounds its rho term), so the radial factor never exceeds
/// s = (tanh(k sup F) + 1) / 2 < 1, and |P w(M)| <= s |P M| for every M (Eq. 30: local
/// contraction about P; not a contraction of the plane). A whole winding keeps G continuous
/// across theta = +-pi; w = -1 mirrors.
struct PolarMap {
  static constexpr int kF = 6, kG = 4;
  std::array<double, 2> center{};  ///< P
  double k = 1.0;                  ///< steepness of the radial factor, > 0
  std::array<double, kF> f{};      ///< f0..f5 of F
  std::array<double, kG> g{};      ///< g0..g3 of G
  int winding = 1;                 ///< w, a whole number in -kMaxWinding..kMaxWinding

  static constexpr int kMaxWinding = 4;

  /// @brief sup F over the plane: f0 + |f1| + |(f2, f3)| + |(f4, f5)|.
  double f_bound() const;
  /// @brief s_i of Eq. 30: (tanh(k sup F) + 1) / 2, below 1 for a valid map.
  double contraction() const;
  /// @brief out[0..1] = the image of in[0..1] (in == out allowed).
  void apply(const double* in, double* out) const;
  /// @brief InputError naming `what` unless every number is finite and within
  /// kMaxCoefficient, k > 0, the winding is whole and in range, and s rounds below 1.
  void validate(const std::string& what) const;
  /// @brief An affine map of R^dim whose spatial rows are x -> P + s (x - P) (the disc about P
  /// that Eq. 30 maps inside itself) and whose other rows are those of `channels`.
  AffineMap shadow(const AffineMap& channels) const;

  bool operator==(const PolarMap& o) const {
    return center == o.center && k == o.k && f == o.f && g == o.g && winding == o.winding;
  }
};

class Ifs;

/// @brief A 2D system ("xy") of polar maps only, with the given probabilities (empty:
/// proportional to s_i^2, the area factor of each map's disc, as Eq. 46 does for affine maps).
Ifs polar_ifs(std::string name, const std::vector<PolarMap>& maps, std::vector<double> probabilities = {});

}  // namespace ifsforge
