#pragma once
/// @file Fractal tops (seed 3.3.5, Eq. 35-37): the tops function tau_F (the largest address of
/// each point of the attractor) per pixel, and the picture warp phi_G o tau_F between two
/// systems with the same number of maps.
#include <cstdint>
#include <vector>

#include "ifsforge/model/ifs.h"
#include "ifsforge/render/frame.h"
#include "ifsforge/core/image.h"

namespace ifsforge {

/// Address digits kept per pixel (4 bits each: systems of at most 16 maps).
constexpr int kTopsDepth = 16;
/// Points per pixel of one round of the chaos game (Eq. 44 with PEPP 16).
constexpr int kTopsPointsPerPixel = 16;
/// Rounds at most, when the count is left to the walk: a round follows while the last one found
/// more than this share of new pixels (thin measure is reached late).
constexpr int kTopsRounds = 16;
constexpr double kTopsNewPixels = 1e-3;
/// A pixel the walk missed is filled from its neighbours when at least this many of its 8 were hit
/// (a pinhole inside the support; a one-pixel gap between two pieces has 6).
constexpr int kTopsFillNeighbours = 7;

struct TopsOptions {
  int width = 256, height = 256;
  /// Chaos-game points; 0: rounds of kTopsPointsPerPixel per pixel until the support is found.
  std::uint64_t iterations = 0;
  std::uint64_t seed = 0;
};

/// @brief Per pixel of `frame`, the largest address (outermost map first, kTopsDepth digits,
/// 4 bits each, digit 0 in the top bits) among the chaos-game points that fell in it, and the
/// plane point that carried it; pixels nothing fell in have no address (`covered` 0). The walk
/// draws the system's own maps with its own probabilities (or transitions); left to choose its
/// count, it goes on in rounds, every other one with Eq. 46's probabilities, until the
/// attractor's thin parts are found; pinholes left inside take their neighbours' top
/// (kTopsFillNeighbours).
struct Tops {
  int width = 0, height = 0;
  std::vector<std::uint64_t> codes;
  std::vector<std::uint8_t> covered;
  std::uint64_t points = 0;  ///< chaos-game points walked
};
Tops tops(const Ifs& ifs, const Frame& frame, const TopsOptions& options);

/// @brief The picture laid on F's frame carried onto G's attractor: each pixel q of G's frame
/// takes the colour of the picture at phi_F(tau_G(q)) (the inverse of phi_G o tau_F, so that G's
/// whole attractor is coloured), found by one chaos game driving F and G with the same map
/// choices, drawn with G's probabilities (G's attractor is the one covered). F and G need the
/// same number of maps (at most 16) and 2 spatial dimensions. Returns RGBA (alpha 0 off G's
/// attractor); the points walked in `points` when given.
Image tops_warp(const Ifs& f, const Frame& f_frame, const Image& picture, const Ifs& g, const Frame& g_frame,
                const TopsOptions& options, std::uint64_t* points = nullptr);

}  // namespace ifsforge
