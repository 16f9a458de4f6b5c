#pragma once
/// @file A terrain's mesh file (terrain_mesh written by extension).
#include <string>

#include "ifsforge/terrain/terrain_mesh.h"

namespace ifsforge {

/// @brief terrain_mesh written by extension (.glb, .obj, .ply, see write_mesh). A .glb with a
/// palette embeds the palette strip (PNG) as the material's base-colour texture and carries no
/// vertex colours (glTF would multiply them into the texture); PLY keeps the vertex colours.
void write_terrain_mesh(const std::string& path, const Terrain& terrain, const TerrainMeshOptions& options = {},
                        int threads = 0);

}  // namespace ifsforge
