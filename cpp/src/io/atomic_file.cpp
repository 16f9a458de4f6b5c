#include "ifsforge/io/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

#include "ifsforge/core/error.h"

namespace ifsforge {

std::string folder_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

void check_writable(const std::string& path) {
  if (path.empty()) throw FileError("no output path given");
  const std::string folder = folder_of(path);
  if (access(folder.c_str(), W_OK) != 0)
    throw FileError("cannot write '" + path + "': folder '" + folder + "' " +
                    (errno == ENOENT ? "does not exist" : std::strerror(errno)));
}

AtomicFile::AtomicFile(const std::string& path) : path_(path) {
  check_writable(path);
  static std::atomic<unsigned> counter{0};
  temporary_ = path + ".tmp-" + std::to_string(getpid()) + "-" + std::to_string(counter++);
  file_ = std::fopen(temporary_.c_str(), "wb");
  if (!file_) throw FileError("cannot write '" + path + "': " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_) std::remove(temporary_.c_str());
}

void AtomicFile::commit() {
  const bool written = std::fflush(file_) == 0 && !std::ferror(file_);
  const int saved = errno;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!written || !closed)
    throw FileError("cannot write '" + path_ + "': " + std::strerror(written ? errno : saved));
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0)
    throw FileError("cannot write '" + path_ + "': " + std::strerror(errno));
  committed_ = true;
}

}  // namespace ifsforge
