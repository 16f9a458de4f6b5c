#pragma once
/// @file Triangle mesh writers: PLY and OBJ of ifsforge's own, glTF binary (.glb) through
/// tinygltf. The library stays behind this header.
#include <optional>
#include <string>
#include <vector>

#include "ifsforge/core/progress.h"
#include "ifsforge/geometry/axes.h"
#include "ifsforge/geometry/triangle_mesh.h"

namespace ifsforge {

struct MeshWriteOptions {
  /// glTF only: a PNG to embed as the material's base colour texture (needs uvs).
  std::string base_color_texture;
  /// glTF only: the mesh/node name.
  std::string name = "ifsforge";
  /// The file's up axis; none: what its reader expects (default_up: glTF and OBJ y, PLY z).
  std::optional<Up> up;
  /// Reports the fraction written; false cancels (Cancelled, and no file is left).
  ProgressCallback progress;
};

/// @brief Writes by extension: .ply (binary; normals, RGBA colours as display values, uvs), .obj
/// (normals and uvs; OBJ has no standard vertex colour, so colours are left out), .glb (binary
/// glTF 2.0 with all attributes, COLOR_0 linear as glTF requires, and the optional texture).
/// Positions and normals are turned to the file's up axis (MeshWriteOptions::up). PLY and OBJ are
/// formatted in parallel (the bytes do not depend on the thread count). Atomic; InputError for an unknown
/// extension or a malformed mesh (indices out of range, attribute counts that do not match).
void write_mesh(const std::string& path, const TriangleMesh& mesh, const MeshWriteOptions& options = {});

}  // namespace ifsforge
