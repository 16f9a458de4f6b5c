#pragma once
/// @file Writes that never leave a partial file: write a temporary beside the target, then
/// rename it over the target. A failure removes the temporary.
#include <cstdio>
#include <string>

namespace ifsforge {

class AtomicFile {
 public:
  /// @brief Opens a temporary beside `path`; FileError names the path when it cannot.
  explicit AtomicFile(const std::string& path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::FILE* file() { return file_; }
  const std::string& temporary_path() const { return temporary_; }
  /// @brief Flushes, closes and renames onto the target; FileError when any step fails.
  void commit();

 private:
  std::string path_, temporary_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

/// @brief Creates a new file named `prefix`, 16 random hex digits, `suffix` (letters and digits
/// between them: safe as any program's argument) with O_EXCL | O_NOFOLLOW, so never a file or
/// link planted at that name; sets `path` to its name and returns its descriptor (write-only,
/// close-on-exec, `mode` before the umask). FileError starting with `failure` when it cannot.
int create_exclusive(const std::string& prefix, const std::string& suffix, int mode, const std::string& failure,
                     std::string& path);

/// @brief The folder of `path`: "." for a bare file name, "/" for a file at the root.
std::string folder_of(const std::string& path);

/// @brief FileError unless `path` can be created (its folder exists and is writable).
void check_writable(const std::string& path);

/// @brief Writes `size` bytes through `file`; FileError naming `path` when the disk refuses.
void write_bytes(std::FILE* file, const char* data, std::size_t size, const std::string& path);

}  // namespace ifsforge
