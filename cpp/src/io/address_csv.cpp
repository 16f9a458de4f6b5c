#include "ifsforge/io/address_csv.h"

#include <cstdio>

#include "ifsforge/io/atomic_file.h"

namespace ifsforge {

void write_address_csv(const std::string& path, const AddressTable& addresses) {
  AtomicFile file(path);
  std::string chunk = "index,address,length,probability\n";
  char number[32];
  for (std::size_t i = 0; i < addresses.size(); ++i) {
    chunk += std::to_string(i);
    chunk += ',';
    chunk += addresses.to_string(i);
    chunk += ',';
    chunk += std::to_string(addresses.lengths[i]);
    chunk += ',';
    std::snprintf(number, sizeof number, "%.17g\n", addresses.probabilities[i]);
    chunk += number;
    if (chunk.size() > (1u << 20)) {
      std::fwrite(chunk.data(), 1, chunk.size(), file.file());
      chunk.clear();
    }
  }
  std::fwrite(chunk.data(), 1, chunk.size(), file.file());
  file.commit();
}

}  // namespace ifsforge
