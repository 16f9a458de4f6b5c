#pragma once
/// @file Reading a user's triangle mesh (PLY, OBJ, OFF, STL) through OpenMesh, which stays
/// behind this header.
#include <string>

#include "ifsforge/io/mesh.h"

namespace ifsforge {

/// @brief The mesh in `path`, polygons triangulated, with per-vertex normals when the file has
/// none. FileError when the file cannot be read; InputError when it holds no triangle.
TriangleMesh read_mesh(const std::string& path);

}  // namespace ifsforge
