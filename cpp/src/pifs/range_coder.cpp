#include "ifsforge/pifs/range_coder.h"

#include "ifsforge/core/error.h"

namespace ifsforge {
namespace {
using range_coding::kProbBits;
using range_coding::kTop;
using range_coding::kMaxLength;
}  // namespace

void RangeEncoder::shift_low() {
  if (static_cast<std::uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
    const std::uint8_t carry = static_cast<std::uint8_t>(low_ >> 32);
    std::uint8_t temp = cache_;
    do {
      out_.push_back(static_cast<std::uint8_t>(temp + carry));
      temp = 0xFF;
    } while (--cache_size_ != 0);
    cache_ = static_cast<std::uint8_t>(low_ >> 24);
  }
  ++cache_size_;
  low_ = (low_ & 0x00FFFFFFu) << 8;
}

std::vector<std::uint8_t> RangeEncoder::finish() {
  for (int i = 0; i < 5; ++i) shift_low();
  return std::move(out_);
}

RangeDecoder::RangeDecoder(const std::uint8_t* data, std::size_t size, std::string where)
    : data_(data), size_(size), where_(std::move(where)) {
  for (int i = 0; i < 5; ++i) code_ = (code_ << 8) | next();
}

std::uint8_t RangeDecoder::next() {
  if (pos_ >= size_) throw InputError(where_ + ": truncated (the transform stream ends early)");
  return data_[pos_++];
}

int RangeDecoder::bit(BitModel& m) {
  const std::uint32_t bound = (range_ >> kProbBits) * m.p;
  int bit;
  if (code_ < bound) {
    range_ = bound;
    bit = 0;
  } else {
    code_ -= bound;
    range_ -= bound;
    bit = 1;
  }
  m.p = m.after(bit);
  while (range_ < kTop) {
    range_ <<= 8;
    code_ = (code_ << 8) | next();
  }
  return bit;
}

unsigned RangeDecoder::tree(BitModel* t, int bits) {
  unsigned node = 1;
  for (int i = 0; i < bits; ++i) node = node * 2 + bit(t[node]);
  return node - (1u << bits);
}

unsigned RangeDecoder::integer(BitModel* length, BitModel (*tail)[24]) {
  unsigned n = 0;
  while (n < kMaxLength && bit(length[n])) ++n;
  if (n == 0) return 0;
  unsigned v = 1;
  for (int i = int(n) - 2; i >= 0; --i) v = (v << 1) | unsigned(bit(tail[n][i]));
  return v;
}

}  // namespace ifsforge
