#pragma once
/// @file Roughness controls: the vertical scaling factors a22_i of fractal interpolation
/// (seed 6.1.3.2, Eq. 94) chosen from one roughness value per direction or colour component.
#include <cstdint>
#include <string>
#include <vector>

#include "ifsforge/core/names.h"

namespace ifsforge {

/// @brief How the signs of a22_i = ±roughness are chosen. The magnitude sets the amplitude of
/// the detail; the signs shape it (all positive repeats the data's trend at every scale,
/// alternating and random signs fold it).
enum class SignPattern { Constant, Alternating, Random };
template <>
struct EnumNames<SignPattern> {
  static constexpr const char* what = "sign pattern";
  static constexpr NamedValue<SignPattern> values[] = {
      {SignPattern::Random, "random"},
      {SignPattern::Alternating, "alternating"},
      {SignPattern::Constant, "constant"}};
};

/// @brief `maps` factors of magnitude |roughness| (< 1) with the given sign pattern; Random
/// draws the signs from Rng(seed, stream), so each direction or component can use its stream.
std::vector<double> vertical_scaling(std::size_t maps, double roughness, SignPattern signs = SignPattern::Random,
                                     std::uint64_t seed = 0, std::uint64_t stream = 0);

/// @brief InputError naming `what` unless every factor is finite with |a22| < 1 (the
/// condition under which the interpolation IFS has an attractor, the graph of a continuous
/// function).
void check_vertical_scaling(const std::vector<double>& a22, const std::string& what);

}  // namespace ifsforge
