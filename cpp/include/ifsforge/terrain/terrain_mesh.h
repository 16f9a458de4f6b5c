#pragma once
/// @file A terrain as a triangle mesh (normals, palette UVs and colours); io/terrain_mesh_file.h writes it.
#include <cmath>
#include <optional>

#include "ifsforge/geometry/axes.h"
#include "ifsforge/geometry/triangle_mesh.h"
#include "ifsforge/terrain/terrain.h"
#include "ifsforge/texture/palette.h"

namespace ifsforge {

struct TerrainMeshOptions {
  /// Close the surface with walls down to `base` and a floor: a watertight solid (every
  /// edge shared by exactly two triangles). Otherwise an open sheet whose only boundary is
  /// the outline.
  bool solid = false;
  /// The floor height of a solid; NaN: 10% of the height range (at least 1% of the
  /// horizontal extent) below the lowest point.
  double base = std::nan("");
  /// write_terrain_mesh: the file's up axis (none: its reader's, see default_up). terrain_mesh
  /// itself always gives ifsforge's axes, (x, y, height).
  std::optional<Up> up;
  /// Vertex colours from this palette by height (empty palette: no colours).
  Palette palette;
};

/// @brief The lattice as a mesh: one vertex per sample (a circular grid's centre is one
/// vertex and its circle closes without a seam), two triangles per cell, counter-clockwise
/// seen from above. Normals from the surface's central differences; uv = (normalised
/// height, 0.5), the coordinate of a palette strip used as base-colour texture.
/// Vertex count: columns x rows (circular: 1 + columns (rows - 1)); a solid adds one floor
/// vertex per outline vertex and one at the floor's centre.
TriangleMesh terrain_mesh(const Terrain& terrain, const TerrainMeshOptions& options = {}, int threads = 0);

}  // namespace ifsforge
