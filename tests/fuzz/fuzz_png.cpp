#include "fuzz_common.h"
#include "ifsforge/io/png.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::with_file(data, size, ".png", [](const std::string& path) { ifsforge::read_png(path); });
  return 0;
}
