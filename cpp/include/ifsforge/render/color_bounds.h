#pragma once
/// @file Bounds of the colour channels for display (seed 6.4.3, Eq. 101).
#include "ifsforge/model/ifs.h"

namespace ifsforge {

/// @brief minR, maxR (and likewise for every extra channel) as the seed estimates them: from a
/// few levels of point recursion, the images w_s(x0) of the start point (on the attractor) for
/// every address s of at most `levels` maps (capped at about 2^20 points). Every value lies in
/// the true range; deeper levels approach its ends. Display values then follow Eq. 101,
/// (v - min) / (max - min).
Bounds color_bounds(const Ifs& ifs, int levels = 8);

}  // namespace ifsforge
