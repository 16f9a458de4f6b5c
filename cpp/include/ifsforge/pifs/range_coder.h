#pragma once
/// @file An adaptive binary range coder (carry-less 32-bit range, 11-bit probabilities) with
/// bit-tree models: the entropy coder of the .pifs transforms and quadtree bits.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ifsforge {

namespace range_coding {
constexpr int kProbBits = 11;
constexpr int kAdapt = 4;  // fast adaptation: a plane codes only a few thousand symbols
constexpr std::uint32_t kTop = 1u << 24;
constexpr unsigned kMaxLength = 24;  // an integer's bit count is coded up to this (unary)
}  // namespace range_coding

/// @brief Probability of a 0 bit, in 1/2048; adapts after each coded bit.
struct BitModel {
  std::uint16_t p = 1024;
  /// @brief The probability once `bit` is coded: a 16th of the way towards the bit seen. The
  /// encoder, the decoder and the sizer all adapt through this.
  std::uint16_t after(int bit) const {
    using namespace range_coding;
    return bit ? std::uint16_t(p - (p >> kAdapt)) : std::uint16_t(p + (((1u << kProbBits) - p) >> kAdapt));
  }
};

/// @brief What RangeEncoder and RangeSizer share: multi-bit symbols as runs of `bit` calls.
template <class Coder>
class RangeSymbols {
 public:
  /// @brief `bits` low bits of `value`, most significant first, through a bit tree of
  /// 2^bits models (`tree` must hold that many).
  void tree(BitModel* tree, int bits, unsigned value) {
    unsigned node = 1;
    for (int i = bits - 1; i >= 0; --i) {
      const int b = (value >> i) & 1;
      self().bit(tree[node], b);
      node = node * 2 + unsigned(b);
    }
  }
  /// @brief A non-negative integer: its bit count coded in `length` (a tree of 32 models) by
  /// an adaptive unary code, the bits below the leading one in `tail` (one model per length, position).
  void integer(BitModel* length, BitModel (*tail)[24], unsigned value) {
    unsigned n = 0;  // the bit length of value, 0 for 0
    for (unsigned v = value; v; v >>= 1) ++n;
    for (unsigned i = 0; i < n; ++i) self().bit(length[i], 1);
    if (n < range_coding::kMaxLength) self().bit(length[n], 0);
    for (int i = int(n) - 2; i >= 0; --i) self().bit(tail[n][i], (value >> i) & 1);
  }

 private:
  Coder& self() { return static_cast<Coder&>(*this); }
};

class RangeEncoder : public RangeSymbols<RangeEncoder> {
 public:
  /// @brief One bit with model `m` (inline: the rate control codes every plane many times).
  void bit(BitModel& m, int bit) {
    using namespace range_coding;
    const std::uint32_t bound = (range_ >> kProbBits) * m.p;
    if (bit == 0) {
      range_ = bound;
    } else {
      low_ += bound;
      range_ -= bound;
    }
    m.p = m.after(bit);
    while (range_ < kTop) {
      range_ <<= 8;
      shift_low();
    }
  }
  std::vector<std::uint8_t> finish();

 private:
  void shift_low();
  std::uint64_t low_ = 0;
  std::uint32_t range_ = 0xFFFFFFFFu;
  std::uint8_t cache_ = 0;
  std::uint64_t cache_size_ = 1;
  std::vector<std::uint8_t> out_;
};

/// @brief The size RangeEncoder's finish() would have for the same bits, without the bytes: the
/// rate control needs only sizes. The encoder writes one byte per shift of its low end: one per
/// renormalisation of the range and five at the end (the first is the cache's initial byte,
/// the last call always flushes), and the range evolves from the bits and models alone, so
/// following the range gives the size exactly while skipping the low end, its carries and
/// the output buffer.
class RangeSizer : public RangeSymbols<RangeSizer> {
 public:
  /// The encoder's steps without its branches (a coded bit is as good as random to the branch
  /// predictor): both outcomes computed, one kept; the renormalisation's shifts counted at
  /// once from the range's leading zeros (it is never 0: a probability stays in [15, 2033]
  /// of 2048, so both outcomes leave at least 2^13 · 15).
  void bit(BitModel& m, int bit) {
    using namespace range_coding;
    const std::uint32_t bound = (range_ >> kProbBits) * m.p;
    range_ = bit ? range_ - bound : bound;
    m.p = m.after(bit);
    const int bytes = __builtin_clz(range_) >> 3;  // shifts by 8 until range_ >= kTop = 2^24
    range_ <<= 8 * bytes;
    shifts_ += std::size_t(bytes);
  }
  /// @brief The bytes RangeEncoder::finish() returns for the bits coded so far.
  std::size_t size() const { return shifts_ + 5; }

 private:
  std::uint32_t range_ = 0xFFFFFFFFu;
  std::size_t shifts_ = 0;
};

/// @brief Decodes what RangeEncoder wrote; InputError naming `where` when it runs past the end.
class RangeDecoder {
 public:
  RangeDecoder(const std::uint8_t* data, std::size_t size, std::string where);
  int bit(BitModel& m);
  unsigned tree(BitModel* tree, int bits);
  unsigned integer(BitModel* length, BitModel (*tail)[24]);
  /// @brief Bytes read so far (the encoder's final flush is 5 bytes; all must be consumed).
  std::size_t consumed() const { return pos_; }

 private:
  std::uint8_t next();
  const std::uint8_t* data_;
  std::size_t size_, pos_ = 0;
  std::uint32_t range_ = 0xFFFFFFFFu, code_ = 0;
  std::string where_;
};

}  // namespace ifsforge
