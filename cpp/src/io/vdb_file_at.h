#pragma once
// The .vdb band writer's file access (src/io only): positioned writes, write-back in pieces that
// hear Ctrl-C, and the content hash that stands for the file's UUID.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/progress.h"

namespace ifsforge::detail {

/// Writes at offsets of one open file, reporting failures as FileError naming the target.
class FileAt {
 public:
  FileAt(int fd, std::string shown) : fd_(fd), shown_(std::move(shown)) {}
  void write(std::uint64_t offset, const char* data, std::size_t size) const {
    while (size > 0) {
      const ssize_t n = ::pwrite(fd_, data, size, static_cast<off_t>(offset));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) throw FileError("cannot write '" + shown_ + "': " + (n < 0 ? std::strerror(errno) : "the disk refused the data (full?)"));
      data += n;
      size -= static_cast<std::size_t>(n);
      offset += static_cast<std::uint64_t>(n);
    }
  }
  /// Starts writing the file's dirty pages to disk without waiting: the commit's fsync then
  /// finds most of them written instead of writing the whole file after its last leaf.
  void start_writeback() const {
#ifdef SYNC_FILE_RANGE_WRITE
    ::sync_file_range(fd_, 0, 0, SYNC_FILE_RANGE_WRITE);  // advice only: the commit's fsync reports errors
#endif
  }
  /// Waits for [0, end) to reach the disk a piece at a time, asking `progress` between pieces:
  /// the commit's fsync then finds little left, and Ctrl-C is heard while the disk catches up.
  void sync_pieces(std::uint64_t end, const ProgressCallback& progress) const {
    constexpr std::uint64_t kPiece = 16u << 20;
    for (std::uint64_t at = 0; at < end; at += kPiece) {
      if (progress && !progress(static_cast<double>(at) / static_cast<double>(end))) throw Cancelled();
#ifdef SYNC_FILE_RANGE_WRITE
      ::sync_file_range(fd_, static_cast<off_t>(at), static_cast<off_t>(std::min(kPiece, end - at)),
                        SYNC_FILE_RANGE_WAIT_BEFORE | SYNC_FILE_RANGE_WRITE | SYNC_FILE_RANGE_WAIT_AFTER);
#endif
    }
  }
  int fd() const { return fd_; }
  const std::string& shown() const { return shown_; }

 private:
  int fd_;
  std::string shown_;
};

/// A content hash as a UUID (8-4-4-4-12 hex) of the bytes [begin, end) of the file `written`
/// (read back through its own descriptor); `file` names it in errors.
std::string content_uuid(const std::string& written, const FileAt& file, std::uint64_t begin, std::uint64_t end,
                         int threads, const ProgressCallback& progress);

}  // namespace ifsforge::detail
