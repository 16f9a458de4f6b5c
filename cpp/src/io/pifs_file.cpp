#include "ifsforge/io/pifs_file.h"

#include <cstdio>

#include "ifsforge/core/error.h"
#include "ifsforge/io/atomic_file.h"

namespace ifsforge {

void write_pifs(const std::string& path, const PifsCode& code) {
  const std::vector<std::uint8_t> bytes = pifs_to_bytes(code);  // fails before the file exists
  AtomicFile out(path);
  if (std::fwrite(bytes.data(), 1, bytes.size(), out.file()) != bytes.size())
    throw FileError("cannot write '" + path + "'");
  out.commit();
}

PifsCode read_pifs(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw FileError("cannot open '" + path + "'");
  std::vector<std::uint8_t> bytes;
  std::uint8_t buffer[65536];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) bytes.insert(bytes.end(), buffer, buffer + n);
  const bool failed = std::ferror(f);
  std::fclose(f);
  if (failed) throw FileError("cannot read '" + path + "'");
  return pifs_from_bytes(bytes.data(), bytes.size(), "'" + path + "'");
}

}  // namespace ifsforge
