#include "ifsforge/io/text_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"

namespace ifsforge {

std::string read_text_file(const std::string& path) {
  struct stat info;
  if (stat(path.c_str(), &info) != 0) throw FileError("cannot read '" + path + "': " + std::strerror(errno));
  if (S_ISDIR(info.st_mode)) throw FileError("cannot read '" + path + "': it is a folder, not a file");
  if (S_ISREG(info.st_mode)) {
    const double bytes = static_cast<double>(info.st_size);
    if (bytes > kMaxTextFileBytes)
      throw InputError(path + ": the file holds " + std::to_string(info.st_size) + " bytes, more than the " +
                       std::to_string(kMaxTextFileBytes >> 20) + " MiB an input file may have");
    // A parsed document (JSON DOM, maps) takes up to ~40 bytes per byte of text.
    check_memory(40.0 * bytes, "reading '" + path + "'");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError("cannot read '" + path + "': " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace ifsforge
