#pragma once
/// @file A terrain as a height-field image (the 16-bit PNG that POV-Ray's height_field, Blender's
/// displacement and game engines read).
#include "ifsforge/core/image.h"
#include "ifsforge/terrain/terrain.h"

namespace ifsforge {

/// @brief One channel, heights mapped linearly from [terrain.min_height, terrain.max_height]
/// to [0, 1] (all 0 for a flat terrain); north up: image row 0 is the terrain's largest y.
/// Pixels are vertex-centred: pixel (0, 0) sits on the outline's north-west corner and pixel
/// (width - 1, height - 1) on its south-east corner.
/// Regular grids: the samples themselves (width and height 0 or equal to the sample counts).
/// Irregular and circular grids: the triangulated surface (the mesh of terrain_mesh.h)
/// resampled by exact barycentric interpolation on a `width` x `height` raster over the
/// outline (0: columns x rows; circular: 2 rows - 1 square); a circular terrain extends its
/// outer circle's heights radially to the square's corners. Independent of `threads`.
Image height_image(const Terrain& terrain, int width = 0, int height = 0, int threads = 0);

}  // namespace ifsforge
