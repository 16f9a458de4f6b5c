#include "vdb_file_at.h"

#include <cstdio>
#include <iterator>
#include <stdexcept>

namespace ifsforge::detail {
namespace {
constexpr std::uint64_t kPrime = 0x100000001b3ull;
}  // namespace

/// The words of `data`, which follow the `done` bytes already hashed: a word begun by the last
/// piece is completed first, a word this piece leaves incomplete waits in `tail`.
void ContentHash::Block::hash(const char* data, std::size_t size) {
  auto word = [&](std::uint64_t w) {
    a = (a ^ w) * kPrime;
    b = (b ^ (w >> 29 | w << 35)) * kPrime;
  };
  std::size_t i = 0;
  for (std::size_t held = done & 7; held && i < size; held = (done + i) & 7) {
    tail[held] = static_cast<unsigned char>(data[i++]);
    if (((done + i) & 7) == 0) {
      std::uint64_t w;
      std::memcpy(&w, tail, 8);
      word(w);
    }
  }
  for (; i + 8 <= size; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, data + i, 8);
    word(w);
  }
  for (; i < size; ++i) tail[(done + i) & 7] = static_cast<unsigned char>(data[i]);
  done += size;
}

ContentHash::Block& ContentHash::block(std::size_t k) {
  std::lock_guard<std::mutex> lock(blocks_mutex_);
  while (blocks_.size() <= k) blocks_.emplace_back();
  return blocks_[k];
}

void ContentHash::add(std::uint64_t offset, const char* data, std::size_t size) {
  if (offset < begin_) {
    const std::uint64_t skip = std::min<std::uint64_t>(size, begin_ - offset);
    data += skip;
    size -= static_cast<std::size_t>(skip);
    offset += skip;
  }
  while (size > 0) {
    const std::uint64_t at = offset - begin_, in_block = at % kBlock;
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(size, kBlock - in_block));
    Block& b = block(static_cast<std::size_t>(at / kBlock));
    std::lock_guard<std::mutex> lock(b.mutex);
    if (in_block != b.done) {
      const auto after = b.early.lower_bound(in_block);
      if (in_block < b.done || (after != b.early.end() && after->first < in_block + n) ||
          (after != b.early.begin() && std::prev(after)->second > in_block))
        throw std::logic_error("write_vdb: a byte of the file was written twice");
      if (b.held.empty()) zeroed_large(b.held, kBlock);
      std::memcpy(b.held.data() + in_block, data, n);
      b.early.emplace_hint(after, in_block, in_block + n);
    } else {
      b.hash(data, n);
      for (auto next = b.early.begin(); next != b.early.end() && next->first == b.done; next = b.early.erase(next))
        b.hash(b.held.data() + next->first, static_cast<std::size_t>(next->second - next->first));
      if (b.early.empty() && !b.held.empty()) ZeroedVector<char>().swap(b.held);
    }
    data += n;
    size -= n;
    offset += n;
  }
}

std::string ContentHash::uuid(std::uint64_t end) {
  const std::uint64_t length = end > begin_ ? end - begin_ : 0;
  const std::size_t blocks = static_cast<std::size_t>((length + kBlock - 1) / kBlock);
  std::uint64_t a = 0xcbf29ce484222325ull, b = 0x9e3779b97f4a7c15ull;
  for (std::size_t k = 0; k < blocks; ++k) {
    Block& block = this->block(k);
    const std::uint64_t size = std::min(kBlock, length - k * kBlock);
    if (block.done != size || !block.early.empty())
      throw std::logic_error("write_vdb: a byte of the file was never written");
    // A last block that is not whole words ends byte by byte, in the first chain only.
    std::uint64_t ha = block.a;
    for (std::uint64_t i = size & ~std::uint64_t(7); i < size; ++i) ha = (ha ^ block.tail[i & 7]) * kPrime;
    a = (a ^ ha) * kPrime;
    b = (b ^ (block.b ^ size)) * kPrime;
  }
  char text[37];
  std::snprintf(text, sizeof text, "%08x-%04x-%04x-%04x-%012llx", unsigned(a >> 32), unsigned((a >> 16) & 0xFFFF),
                unsigned(a & 0xFFFF), unsigned(b >> 48), static_cast<unsigned long long>(b & 0xFFFFFFFFFFFFull));
  return text;
}

}  // namespace ifsforge::detail
