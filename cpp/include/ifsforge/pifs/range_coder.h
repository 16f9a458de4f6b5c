#pragma once
/// @file An adaptive binary range coder (carry-less 32-bit range, 11-bit probabilities) with
/// bit-tree models: the entropy coder of the .pifs transforms and quadtree bits.
#include <cstdint>
#include <string>
#include <vector>

namespace ifsforge {

namespace range_coding {
constexpr int kProbBits = 11;
constexpr int kAdapt = 4;  // fast adaptation: a plane codes only a few thousand symbols
constexpr std::uint32_t kTop = 1u << 24;
}  // namespace range_coding

/// @brief Probability of a 0 bit, in 1/2048; adapts after each coded bit.
struct BitModel {
  std::uint16_t p = 1024;
};

class RangeEncoder {
 public:
  /// @brief One bit with model `m` (inline: the rate control codes every plane many times).
  void bit(BitModel& m, int bit) {
    using namespace range_coding;
    const std::uint32_t bound = (range_ >> kProbBits) * m.p;
    if (bit == 0) {
      range_ = bound;
      m.p += ((1u << kProbBits) - m.p) >> kAdapt;
    } else {
      low_ += bound;
      range_ -= bound;
      m.p -= m.p >> kAdapt;
    }
    while (range_ < kTop) {
      range_ <<= 8;
      shift_low();
    }
  }
  /// @brief `bits` low bits of `value`, most significant first, through a bit tree of
  /// 2^bits models (`tree` must hold that many).
  void tree(BitModel* tree, int bits, unsigned value);
  /// @brief A non-negative integer: its bit count coded in `length` (a tree of 32 models) by
  /// an adaptive unary code, the bits below the leading one in `tail` (one model per length, position).
  void integer(BitModel* length, BitModel (*tail)[24], unsigned value);
  std::vector<std::uint8_t> finish();

 private:
  void shift_low();
  std::uint64_t low_ = 0;
  std::uint32_t range_ = 0xFFFFFFFFu;
  std::uint8_t cache_ = 0;
  std::uint64_t cache_size_ = 1;
  std::vector<std::uint8_t> out_;
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
