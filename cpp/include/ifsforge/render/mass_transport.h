#pragma once
/// @file The Markov operator on pixel images (Eq. 50, and its vector form Eq. 71-72), shared by
/// the constant mass algorithm (5.4) and the vector recurrent photo-copy algorithm (5.12.1).
#include <cstdint>
#include <vector>

#include "ifsforge/render/pixel_space.h"

namespace ifsforge {

/// @brief How mass moves: C component images; map j carries weight(i, j) of the mass of
/// component i (at each pixel) to component target[j], at the pixel holding w_j(pixel centre).
/// CMA: one component, weight(0, j) = p_j. Photo-copy: N components, weight(i, j) = P(i, j),
/// target[j] = j (Eq. 72).
struct TransportPlan {
  int components = 1;
  std::vector<double> weight;       ///< components x maps
  std::vector<int> target;          ///< per map
  double condensation_share = 0.0;  ///< p_0: mass spread evenly over the condensation set each step
  double threshold = 1e-3;          ///< stop when the L1 change of the normalised mass is below
  long long max_iterations = 1000;
  /// True: a pixel's mass, taken as spread evenly over the pixel about its centroid, is shared
  /// among the cells its image overlaps (a box with the image's mean and variance along x and
  /// y). False: all of it goes to the cell holding the image of the pixel's centre (the seed's
  /// rounding: sharper binary images, a coarser measure).
  bool spread = true;
};

/// @brief The "spread" parameter of the mass algorithms: box, none, or automatic (none for
/// binary images, where only coverage matters, box otherwise).
RendererParameter spread_parameter();
bool spread_mass(const std::string& value, bool binary);

/// @brief The mass of each component on each pixel where it is not zero (fractions of the
/// total, which stays 1: mass leaving the image is dropped and the rest rescaled), and
/// mass-weighted channel means.
struct TransportResult {
  std::vector<std::uint32_t> pixel;  ///< per entry
  std::vector<int> component;        ///< per entry
  std::vector<double> mass;          ///< per entry
  std::vector<float> channels;   ///< pixels x channels
  long long iterations = 0;
  double change = 0.0;           ///< L1 change of the last iteration
  std::uint64_t operations = 0;  ///< map applications
};

/// @brief Iterates from uniform mass until the change is below the threshold and the support
/// no longer changes (or max_iterations). Integer (fixed-point) mass: the result does not
/// depend on `threads`. Only the pixels holding mass are visited, each component's apart
/// when there are neither centroids nor channels to keep.
TransportResult transport_mass(const Ifs& ifs, const PixelSpace& space, const TransportPlan& plan,
                               const RenderOptions& options);

}  // namespace ifsforge
