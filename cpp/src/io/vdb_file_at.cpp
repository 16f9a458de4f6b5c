#include "vdb_file_at.h"

#include <array>
#include <cstdio>
#include <memory>
#include <vector>

#include "ifsforge/core/parallel.h"

namespace ifsforge::detail {

// Blocks hashed in parallel eight bytes at a time, then the blocks' hashes in order.
std::string content_uuid(const std::string& written, const FileAt& file, std::uint64_t begin, std::uint64_t end,
                         int threads, const ProgressCallback& progress) {
  struct Reader {
    int fd;
    ~Reader() { if (fd >= 0) ::close(fd); }
  } reader{::open(written.c_str(), O_RDONLY)};
  if (reader.fd < 0) throw FileError("cannot write '" + file.shown() + "': cannot read it back: " + std::strerror(errno));
  constexpr std::uint64_t kBlock = 4u << 20, kPrime = 0x100000001b3ull;
  const std::size_t blocks = static_cast<std::size_t>((end - begin + kBlock - 1) / kBlock);
  std::vector<std::array<std::uint64_t, 2>> hashes(blocks);
  // Left unset: each block is read over before it is hashed.
  std::vector<std::unique_ptr<char[]>> buffers(threads);
  for (auto& buffer : buffers) buffer.reset(new char[kBlock]);
  parallel_jobs(blocks, static_cast<int>(buffers.size()), [&](std::size_t k, int worker) {
    char* data = buffers[worker].get();
    const std::uint64_t at = begin + k * kBlock, size = std::min(kBlock, end - at);
    for (std::uint64_t done = 0; done < size;) {
      const ssize_t n = ::pread(reader.fd, data + done, size - done, static_cast<off_t>(at + done));
      if (n <= 0 && !(n < 0 && errno == EINTR)) throw FileError("cannot write '" + file.shown() + "': cannot read it back");
      if (n > 0) done += static_cast<std::uint64_t>(n);
    }
    std::uint64_t a = 0xcbf29ce484222325ull, b = 0x84222325cbf29ce4ull, word = 0;
    std::size_t i = 0;
    for (; i + 8 <= size; i += 8) {
      std::memcpy(&word, data + i, 8);
      a = (a ^ word) * kPrime;
      b = (b ^ (word >> 29 | word << 35)) * kPrime;
    }
    for (; i < size; ++i) a = (a ^ static_cast<unsigned char>(data[i])) * kPrime;
    hashes[k] = {a, b ^ size};
  }, progress);
  std::uint64_t a = 0xcbf29ce484222325ull, b = 0x9e3779b97f4a7c15ull;
  for (const auto& h : hashes) {
    a = (a ^ h[0]) * kPrime;
    b = (b ^ h[1]) * kPrime;
  }
  char text[37];
  std::snprintf(text, sizeof text, "%08x-%04x-%04x-%04x-%012llx", unsigned(a >> 32), unsigned((a >> 16) & 0xFFFF),
                unsigned(a & 0xFFFF), unsigned(b >> 48), static_cast<unsigned long long>(b & 0xFFFFFFFFFFFFull));
  return text;
}

}  // namespace ifsforge::detail
