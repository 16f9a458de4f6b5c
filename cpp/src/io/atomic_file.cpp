#include "ifsforge/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <random>

#include "ifsforge/core/error.h"

namespace ifsforge {

std::string folder_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

void check_writable(const std::string& path) {
  if (path.empty()) throw FileError("no output path given");
  // The output is written beside the target and renamed over it: that would replace a device
  // node, a FIFO or a symbolic link with a regular file, so those are refused.
  struct stat info;
  if (lstat(path.c_str(), &info) == 0 && !S_ISREG(info.st_mode)) {
    const char* kind = S_ISLNK(info.st_mode)   ? "a symbolic link"
                       : S_ISDIR(info.st_mode) ? "a folder"
                       : S_ISFIFO(info.st_mode) ? "a FIFO"
                       : S_ISSOCK(info.st_mode) ? "a socket"
                                                : "a device";
    throw FileError("cannot write '" + path + "': it is " + kind +
                    "; ifsforge writes only regular files (give the path of a new or regular file)");
  }
  const std::string folder = folder_of(path);
  if (access(folder.c_str(), W_OK) != 0)
    throw FileError("cannot write '" + path + "': folder '" + folder + "' " +
                    (errno == ENOENT ? "does not exist" : std::strerror(errno)));
}

int create_exclusive(const std::string& prefix, const std::string& suffix, int mode, const std::string& failure,
                     std::string& path) {
  // A name nobody can guess, created only if nothing (not even a symbolic link) stands there:
  // a link planted at a predictable name would have redirected the write to another file.
  static std::atomic<std::uint64_t> counter{0};
  std::random_device entropy;
  for (int attempt = 0; attempt < 64; ++attempt) {
    const std::uint64_t mark = (std::uint64_t(entropy()) << 32 ^ entropy()) + counter++;
    char digits[17];
    std::snprintf(digits, sizeof digits, "%016llx", static_cast<unsigned long long>(mark));
    path = prefix + digits + suffix;
    const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, mode);
    if (fd >= 0) return fd;
    path.clear();  // never ours to remove
    if (errno != EEXIST) throw FileError(failure + ": " + std::strerror(errno));
  }
  throw FileError(failure + ": no free temporary name");
}

AtomicFile::AtomicFile(const std::string& path) : path_(path) {
  check_writable(path);
  const int fd = create_exclusive(path + ".tmp-", "", 0666, "cannot write '" + path + "'", temporary_);
  file_ = fdopen(fd, "wb");
  if (!file_) {
    const int saved = errno;
    close(fd);
    std::remove(temporary_.c_str());
    temporary_.clear();
    throw FileError("cannot write '" + path + "': " + std::strerror(saved));
  }
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_ && !temporary_.empty()) std::remove(temporary_.c_str());
}

void AtomicFile::commit() {
  const bool written = std::fflush(file_) == 0 && !std::ferror(file_) && fsync(fileno(file_)) == 0;
  const int saved = errno;
  const long position = std::ftell(file_);
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!written || !closed)
    throw FileError("cannot write '" + path_ + "': " + std::strerror(written ? errno : saved));
  // The bytes on disk must be the bytes written (a writer with its own stream checks its own).
  struct stat info;
  if (position > 0 && (stat(temporary_.c_str(), &info) != 0 || info.st_size != position))
    throw FileError("cannot write '" + path_ + "': only part of the file reached the disk");
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0)
    throw FileError("cannot write '" + path_ + "': " + std::strerror(errno));
  committed_ = true;
}

void write_bytes(std::FILE* file, const char* data, std::size_t size, const std::string& path) {
  if (size && std::fwrite(data, 1, size, file) != size)
    throw FileError("cannot write '" + path + "': " + std::strerror(errno));
}

}  // namespace ifsforge
