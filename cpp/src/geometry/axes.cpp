#include "ifsforge/geometry/axes.h"

#include <algorithm>
#include <filesystem>

#include "ifsforge/core/error.h"
#include "ifsforge/geometry/triangle_mesh.h"

namespace ifsforge {

Up up_from_string(const std::string& text, const std::string& what) {
  if (text == "y") return Up::y;
  if (text == "z") return Up::z;
  throw InputError(what + " is 'y' or 'z', not '" + text + "'");
}

const char* to_string(Up up) { return up == Up::y ? "y" : "z"; }

Up default_up(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".glb" || ext == ".gltf" || ext == ".obj" ? Up::y : Up::z;
}

void orient(TriangleMesh& mesh, Up up) {
  if (up == Up::z) return;
  for (auto& p : mesh.positions) p = oriented(p, up);
  for (auto& n : mesh.normals) n = oriented(n, up);
}

}  // namespace ifsforge
