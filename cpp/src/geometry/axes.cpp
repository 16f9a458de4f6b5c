#include "ifsforge/geometry/axes.h"

#include <algorithm>
#include <filesystem>

#include "ifsforge/core/error.h"
#include "ifsforge/geometry/triangle_mesh.h"

namespace ifsforge {

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
