#pragma once
// The .vdb band writer's file access (src/io only): positioned writes, write-back and flushes that
// overlap the writing, waits in pieces that hear Ctrl-C, and the content hash that stands for the
// file's UUID, taken as the bytes are written.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "ifsforge/core/error.h"
#include "ifsforge/core/pages.h"
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

/// Flushes what has been written to the disk on a thread of its own (fdatasync), one flush at a
/// time, while the writer goes on: the disk's cache flush, which dominates a commit's fsync on a
/// virtual disk, then overlaps the work instead of following it, and the commit finds little left.
/// A flush's failure is kept and reported by finish() (a failed flush's error is not seen again
/// by a later fsync of the same file).
class BackgroundSync {
 public:
  explicit BackgroundSync(const FileAt& file) : file_(file) {}
  ~BackgroundSync() {
    if (thread_.joinable()) thread_.join();
  }
  BackgroundSync(const BackgroundSync&) = delete;
  BackgroundSync& operator=(const BackgroundSync&) = delete;
  /// After a piece of the file was written: starts its write-back and, unless one is running, a
  /// flush of everything written so far. Thread-safe.
  void written() {
    file_.start_writeback();
    std::lock_guard<std::mutex> lock(mutex_);
    if (running_.load() || error_) return;
    if (thread_.joinable()) thread_.join();  // done: it cleared running_ as it ended
    running_ = true;
    thread_ = std::thread([this] {
      if (::fdatasync(file_.fd()) != 0) error_ = errno;
      running_ = false;
    });
  }
  /// Waits for the flush running, if any; FileError if a flush failed.
  void finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (thread_.joinable()) thread_.join();
    if (error_) throw FileError("cannot write '" + file_.shown() + "': " + std::strerror(error_));
  }
  /// Once the whole file is written: its last flush (fsync: the commit's then finds nothing), on the
  /// calling thread while the one running (if any) goes on, so that the disk's two cache flushes
  /// overlap instead of following each other (both writer threads sleep through them); then
  /// finish(). FileError if either failed.
  void flush_and_finish() {
    const int failed = ::fsync(file_.fd()) != 0 ? errno : 0;
    finish();
    if (failed) throw FileError("cannot write '" + file_.shown() + "': " + std::strerror(failed));
  }

 private:
  const FileAt& file_;
  std::mutex mutex_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<int> error_{0};
};

/// The content hash that stands for the file's UUID, taken from the bytes as they are written
/// (the file is never read back): FNV-style chains over 8-byte words of 4 MB blocks of the file
/// from `begin`, then the blocks' hashes in order. A block's words are hashed in file order;
/// bytes that reach a block before the bytes in front of them are copied into the block's buffer
/// (huge pages, made when first needed) until those come, so pieces may be added in any order,
/// from any thread, each byte once.
class ContentHash {
 public:
  explicit ContentHash(std::uint64_t begin) : begin_(begin) {}
  ContentHash(const ContentHash&) = delete;
  ContentHash& operator=(const ContentHash&) = delete;
  /// The file's bytes [offset, offset + size); those before `begin` are not hashed. Thread-safe.
  void add(std::uint64_t offset, const char* data, std::size_t size);
  /// The hash of [begin, end) as a UUID (8-4-4-4-12 hex), once every byte of it was added
  /// (std::logic_error otherwise).
  std::string uuid(std::uint64_t end);

 private:
  static constexpr std::uint64_t kBlock = 4u << 20;
  struct Block {
    std::mutex mutex;
    std::uint64_t a = 0xcbf29ce484222325ull, b = 0x84222325cbf29ce4ull;
    std::uint64_t done = 0;                 ///< bytes hashed from the block's start
    unsigned char tail[8] = {};             ///< a word begun but not complete
    std::map<std::uint64_t, std::uint64_t> early;  ///< bytes ahead of `done` in `held`: start -> end
    ZeroedVector<char> held;                ///< the block's early bytes, at their place in it
    void hash(const char* data, std::size_t size);
  };
  Block& block(std::size_t k);

  std::uint64_t begin_;
  std::mutex blocks_mutex_;
  std::deque<Block> blocks_;  ///< grows at the back: references stay valid
};

/// Writes through a FileAt and hashes what it writes (ContentHash).
class HashedWriter {
 public:
  HashedWriter(const FileAt& file, ContentHash& hash) : file_(file), hash_(hash) {}
  void write(std::uint64_t offset, const char* data, std::size_t size) const {
    file_.write(offset, data, size);
    hash_.add(offset, data, size);
  }

 private:
  const FileAt& file_;
  ContentHash& hash_;
};

}  // namespace ifsforge::detail
