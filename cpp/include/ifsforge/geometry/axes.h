#pragma once
/// @file The one up-axis convention of the mesh files. ifsforge computes in right-handed
/// axes with z up (x east, y north), as Blender does. A file written "y up" holds the same
/// right-handed shape rotated so that our z is its y: (x, y, z) -> (x, z, -y), which glTF
/// (the spec) and OBJ (Blender's importer: forward -Z, up Y) expect and turn back to z up.
/// PLY has no convention and Blender's PLY importer converts nothing, so PLY stays z up.
#include <array>
#include <optional>
#include <string>

#include "ifsforge/core/names.h"

namespace ifsforge {

struct TriangleMesh;

enum class Up { y, z };
template <>
struct EnumNames<Up> {
  static constexpr const char* what = "up axis";
  static constexpr NamedValue<Up> values[] = {{Up::y, "y"}, {Up::z, "z"}};
};

/// @brief The up axis a reader of `path` expects by its extension: .glb/.gltf/.obj y, else z.
Up default_up(const std::string& path);

/// @brief A point or direction from our z-up axes into a file's axes: the one place where the
/// axes are swapped.
inline std::array<float, 3> oriented(float x, float y, float z, Up up) {
  if (up == Up::y) return {x, z, -y};
  return {x, y, z};
}
inline std::array<float, 3> oriented(const std::array<float, 3>& p, Up up) { return oriented(p[0], p[1], p[2], up); }

/// @brief The mesh's positions and normals from our z-up axes into `up` axes (a rotation:
/// triangle winding stays counter-clockwise from outside).
void orient(TriangleMesh& mesh, Up up);

}  // namespace ifsforge
