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

struct TopsOptions {
  int width = 256, height = 256;
  std::uint64_t iterations = 0;  ///< chaos-game points; 0: 16 per pixel (Eq. 44 with PEPP 16)
  std::uint64_t seed = 0;
};

/// @brief Per pixel of `frame`, the largest address (outermost map first, kTopsDepth digits,
/// 4 bits each, digit 0 in the top bits) among the chaos-game points that fell in it, and the
/// plane point that carried it; pixels nothing fell in have no address (`covered` 0).
struct Tops {
  int width = 0, height = 0;
  std::vector<std::uint64_t> codes;
  std::vector<std::uint8_t> covered;
};
Tops tops(const Ifs& ifs, const Frame& frame, const TopsOptions& options);

/// @brief The picture laid on F's frame carried onto G's attractor: each pixel q of G's frame
/// takes the colour of the picture at phi_F(tau_G(q)) (the inverse of phi_G o tau_F, so that G's
/// whole attractor is coloured), found by one chaos game driving F and G with the same map
/// choices. F and G need the same number of maps (at most 16) and 2 spatial dimensions.
/// Returns RGBA (alpha 0 off G's attractor).
Image tops_warp(const Ifs& f, const Frame& f_frame, const Image& picture, const Ifs& g, const Frame& g_frame,
                const TopsOptions& options);

}  // namespace ifsforge
