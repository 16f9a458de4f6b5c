#include "fuzz_common.h"
#include "ifsforge/io/pifs_file.h"
#include "ifsforge/pifs/decoder.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::with_file(data, size, ".pifs", [](const std::string& path) {
    const ifsforge::PifsCode code = ifsforge::read_pifs(path);
    // A code that reads must decode: its transforms index its own planes and domains. Small
    // images only, so a fuzzed 60000x60000 header costs the reader's checks, not a decode.
    if (static_cast<double>(code.width) * code.height <= 256.0 * 256.0) ifsforge::pifs_decode(code);
  });
  return 0;
}
