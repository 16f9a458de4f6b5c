#pragma once
/// @file Optional post-filter: softens the step at range-block edges that a blocky code leaves.
#include "ifsforge/pifs/code.h"
#include "ifsforge/pifs/domain_search.h"

namespace ifsforge {

/// @brief Blends the pixel pair on either side of every range-cell edge of `plane` (decoded at
/// scale 2^log_scale into `raster`) 3:1 toward each other; edges of cells under 4 pixels are left.
void deblock(const PifsCode& code, const PifsPlane& plane, int log_scale, PifsRaster& raster);

}  // namespace ifsforge
