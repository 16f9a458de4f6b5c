#include "fuzz_common.h"
#include "ifsforge/io/fractint.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::with_text(data, size, [](const std::string& text) { ifsforge::parse_fractint(text, "fuzz.ifs"); });
  return 0;
}
