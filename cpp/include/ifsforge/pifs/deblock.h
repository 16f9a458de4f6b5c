#pragma once
/// @file Optional post-filter: softens the step at range-block edges that a blocky code leaves.
#include "ifsforge/pifs/code.h"
#include "ifsforge/pifs/domain_search.h"

namespace ifsforge {

/// @brief Spreads the step at every range-cell edge of `plane` (decoded at scale 2^log_scale into
/// `raster`) as a ramp as wide as the scale on each side: gently, and only between smooth sides,
/// at the plane's own size; fully when magnified (deblock.cpp's strengths). Cells under 4 ramp
/// widths are left. The same result on any number of `threads`.
void deblock(const PifsCode& code, const PifsPlane& plane, int log_scale, PifsRaster& raster, int threads = 1);

}  // namespace ifsforge
