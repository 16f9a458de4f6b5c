#pragma once
/// @file Morphing between two systems. The continuity theorem (seed chapter 4) says the
/// attractor depends continuously on the maps' coefficients, so a system whose coefficients
/// move continuously with time animates smoothly, frame after frame, as long as every
/// intermediate system keeps an attractor.
#include "ifsforge/model/ifs.h"

namespace ifsforge {

/// @brief The system between `from` (t = 0) and `to` (t = 1), t in [0, 1]; both must share
/// a layout. The spatial block of each map moves in the parameters of Eq. 5 and its 3D
/// analogue (scales, shears and translations linearly, angles along the shorter arc, a
/// reflection through a signed factor that passes through 0); every other coefficient and
/// the probabilities move linearly. The system with fewer maps is first padded by repeating
/// its last map and sharing that map's probability among the copies, which changes neither
/// its attractor nor its measure. Render windows and views in the systems' render defaults
/// are interpolated when both have them.
Ifs morph(const Ifs& from, const Ifs& to, double t);

/// @brief `ifs` with `maps` maps (>= ifs.size()): the last map repeated, its probability
/// shared equally among the copies.
Ifs pad_maps(const Ifs& ifs, std::size_t maps);

}  // namespace ifsforge
