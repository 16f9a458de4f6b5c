#include "ifsforge/io/terrain_mesh_file.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>

#include "ifsforge/io/atomic_file.h"
#include "ifsforge/io/mesh.h"
#include "ifsforge/io/png.h"

namespace ifsforge {

void write_terrain_mesh(const std::string& path, const Terrain& terrain, const TerrainMeshOptions& options,
                        int threads) {
  check_writable(path);
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  const bool textured = ext == ".glb" && !options.palette.colors.empty();
  // glTF multiplies COLOR_0 into the base colour: with the palette as texture, no vertex colours.
  TerrainMeshOptions build = options;
  if (textured) build.palette.colors.clear();
  const TriangleMesh mesh = terrain_mesh(terrain, build, threads);
  MeshWriteOptions write;
  write.name = "ifsforge_terrain";
  write.up = options.up;
  if (!textured) {
    write_mesh(path, mesh, write);
    return;
  }
  // The glTF embeds the palette strip's PNG bytes: write them to a temporary file first.
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path strip = std::filesystem::temp_directory_path() /
                                      ("ifsforge-palette-" + std::to_string(::getpid()) + "-" +
                                       std::to_string(counter++) + ".png");
  struct Remove {
    std::filesystem::path p;
    ~Remove() {
      std::error_code ignored;
      std::filesystem::remove(p, ignored);
    }
  } remove{strip};
  write_png(strip.string(), palette_image(options.palette, 1), 8);
  write.base_color_texture = strip.string();
  write_mesh(path, mesh, write);
}

}  // namespace ifsforge
