#pragma once
/// @file Exact points of the attractor that random samples rarely reach.
#include <vector>

#include "ifsforge/model/ifs.h"

namespace ifsforge {

/// @brief W^d(F): the fixed points F of the contractive maps and their images under every
/// address of length <= d (at most ~4096 points; a recurrent system's addresses follow its
/// transitions). They lie on the attractor of a hyperbolic
/// system and include its low-probability extremes (the fern's stem foot is the fixed point
/// of a map of probability 0.01 that a million random samples never get near).
std::vector<Point> attractor_extremes(const Ifs& ifs);

}  // namespace ifsforge
