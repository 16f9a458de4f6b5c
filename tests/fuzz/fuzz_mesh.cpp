// The mesh reader picks its parser by extension: the first byte of the input chooses one.
#include "fuzz_common.h"
#include "ifsforge/io/mesh_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const char* kExtensions[] = {".ply", ".obj", ".off", ".stl"};
  if (size == 0) return 0;
  fuzz::with_file(data + 1, size - 1, kExtensions[data[0] % 4], [](const std::string& path) { ifsforge::read_mesh(path); });
  return 0;
}
