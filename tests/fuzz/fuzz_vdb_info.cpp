#include "fuzz_common.h"
#include "ifsforge/io/vdb.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::with_file(data, size, ".vdb", [](const std::string& path) { ifsforge::read_vdb_info(path); });
  return 0;
}
