// The .vdb readers: the header summary (vdb info) and the fit's 3D target (a float grid).
#include "fuzz_common.h"
#include "ifsforge/io/vdb.h"
#include "ifsforge/io/voxel_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::with_file(data, size, ".vdb", [](const std::string& path) { ifsforge::read_vdb_info(path); });
  fuzz::with_file(data, size, ".vdb", [](const std::string& path) { ifsforge::read_voxel_target(path, {16}); });
  return 0;
}
