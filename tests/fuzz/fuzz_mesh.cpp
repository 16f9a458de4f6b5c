// The mesh reader picks its parser by extension: the first byte of the input chooses one. Each
// input is also voxelised as the fit's 3D target (OpenVDB's mesh-to-level-set), at 16 voxels.
#include "fuzz_common.h"
#include "ifsforge/io/mesh_reader.h"
#include "ifsforge/io/voxel_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const char* kExtensions[] = {".ply", ".obj", ".off", ".stl"};
  if (size == 0) return 0;
  fuzz::with_file(data + 1, size - 1, kExtensions[data[0] % 4], [](const std::string& path) {
    ifsforge::read_mesh(path);
    ifsforge::read_voxel_target(path, {16});
  });
  return 0;
}
