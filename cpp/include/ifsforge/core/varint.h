#pragma once
/// @file LEB128 variable-length integers: the compact wire format of job results sent between
/// machines (small counts and key deltas take one byte).
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "ifsforge/core/error.h"

namespace ifsforge {

/// @brief Writes `value` at `at` (at most 10 bytes); returns the end of what it wrote.
inline char* write_varint(char* at, std::uint64_t value) {
  while (value >= 0x80) {
    *at++ = static_cast<char>((value & 0x7F) | 0x80);
    value >>= 7;
  }
  *at++ = static_cast<char>(value);
  return at;
}

inline void put_varint(std::string& out, std::uint64_t value) {
  char bytes[10];
  out.append(bytes, write_varint(bytes, value));
}

/// Varints written through a raw pointer into room reserved for `values` of them (10 bytes
/// each at most, left uninitialised): an encoder's inner loop without a capacity check per byte.
class VarintBuffer {
 public:
  explicit VarintBuffer(std::size_t values) : data_(new char[values * 10 + 1]), at_(data_.get()) {}
  void put(std::uint64_t value) { at_ = write_varint(at_, value); }
  std::string str() const { return std::string(data_.get(), at_); }

 private:
  std::unique_ptr<char[]> data_;
  char* at_;
};

/// Reads varints from a byte string; a truncated or over-long one is an InputError naming `what`.
class VarintReader {
 public:
  /// `bytes` must outlive the reader (a view: a driver reads its workers' results in place).
  VarintReader(std::string_view bytes, const char* what) : bytes_(bytes), what_(what) {}
  std::uint64_t next() {
    // One byte: most key deltas and counts.
    if (at_ < bytes_.size() && !(static_cast<unsigned char>(bytes_[at_]) & 0x80))
      return static_cast<unsigned char>(bytes_[at_++]);
    std::uint64_t value = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (at_ >= bytes_.size()) throw InputError(std::string(what_) + ": truncated");
      const auto byte = static_cast<unsigned char>(bytes_[at_++]);
      value |= std::uint64_t(byte & 0x7F) << shift;
      if (!(byte & 0x80)) return value;
    }
    throw InputError(std::string(what_) + ": malformed integer");
  }
  bool done() const { return at_ == bytes_.size(); }
  /// Bytes read so far.
  std::size_t offset() const { return at_; }

 private:
  std::string_view bytes_;
  const char* what_;
  std::size_t at_ = 0;
};

}  // namespace ifsforge
