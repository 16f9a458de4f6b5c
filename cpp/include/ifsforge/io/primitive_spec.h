#pragma once
/// @file Primitives named by spec strings; "mesh:PATH" reads the mesh file.
#include <string>
#include <vector>

#include "ifsforge/vector/primitives.h"

namespace ifsforge {

/// @brief "line", "circle", "triangle", "square" (each also "-outline" except line), "sphere",
/// "box", "cone", "cylinder", "torus", or "mesh:PATH" (PLY, OBJ, OFF or STL, read through
/// OpenMesh). InputError lists the choices; FileError names an unreadable mesh.
Primitive parse_primitive(const std::string& spec);
/// @brief A comma-separated list of specs ("sphere,box,cone"), in order: the primitive index
/// of the 4D/7D models (Eq. 99, 107) selects from it.
std::vector<Primitive> parse_primitives(const std::string& specs);

}  // namespace ifsforge
