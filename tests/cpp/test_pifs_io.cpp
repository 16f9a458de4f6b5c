// The .pifs file and its range coder: exact round trips, and truncated or corrupted files
// refused with a message saying so (the reader is a fuzz target: no input may crash it).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include "ifsforge/core/error.h"
#include "ifsforge/io/pifs_file.h"
#include "ifsforge/pifs/decoder.h"
#include "ifsforge/pifs/encoder.h"
#include "ifsforge/pifs/range_coder.h"
#include "ifsforge/pifs/residual.h"

using namespace ifsforge;

namespace {

/// A code by quality (the fractal code alone), or by ratio (with the residual layer).
PifsCode sample_code(bool residual = false) {
  Image im(70, 50, 3);
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 70; ++x)
      for (int c = 0; c < 3; ++c) im.at(x, y, c) = float(0.5 + 0.4 * std::sin(x * 0.3 + c) * std::cos(y * 0.2));
  PifsEncodeOptions o;
  o.quality = 3;
  if (residual) o.ratio = 6;
  return pifs_encode(im, o);
}

std::string message_of(const std::vector<std::uint8_t>& bytes) {
  try {
    pifs_from_bytes(bytes.data(), bytes.size(), "test.pifs");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(RangeCoder, RoundTripsRandomSymbols) {
  std::mt19937 rng(5);
  std::vector<int> bits, trees, ints;
  for (int i = 0; i < 5000; ++i) {
    bits.push_back(rng() % 10 < 2);
    trees.push_back(int(rng() % 32));
    ints.push_back(int(rng() % (1u << (rng() % 20))));
  }
  BitModel b, t[32], length[32], tail[25][24];
  RangeEncoder enc;
  for (int i = 0; i < 5000; ++i) {
    enc.bit(b, bits[i]);
    enc.tree(t, 5, unsigned(trees[i]));
    enc.integer(length, tail, unsigned(ints[i]));
  }
  const std::vector<std::uint8_t> bytes = enc.finish();
  BitModel b2, t2[32], length2[32], tail2[25][24];
  RangeDecoder dec(bytes.data(), bytes.size(), "test");
  for (int i = 0; i < 5000; ++i) {
    ASSERT_EQ(dec.bit(b2), bits[i]);
    ASSERT_EQ(int(dec.tree(t2, 5)), trees[i]);
    ASSERT_EQ(int(dec.integer(length2, tail2)), ints[i]);
  }
  EXPECT_EQ(dec.consumed(), bytes.size());
}

TEST(RangeCoder, SizerCountsTheEncodersBytes) {
  // Streams from nearly certain to even bits (long runs of shifts, carries through 0xFF bytes),
  // every length up to 3000 symbols, and nothing coded at all.
  for (const int percent : {0, 1, 20, 50, 97}) {
    std::mt19937 rng(unsigned(percent) + 11);
    BitModel b, t[32], length[32], tail[25][24];
    BitModel sb, st[32], slength[32], stail[25][24];
    RangeEncoder enc;
    RangeSizer sizer;
    for (int i = 0; i <= 3000; ++i) {
      RangeEncoder copy = enc;
      ASSERT_EQ(sizer.size(), copy.finish().size()) << percent << "% ones, " << i << " symbols";
      const int bit = int(rng() % 100) < percent;
      const unsigned tree = rng() % 32, value = rng() % (1u << (rng() % 20));
      enc.bit(b, bit);
      sizer.bit(sb, bit);
      enc.tree(t, 5, tree);
      sizer.tree(st, 5, tree);
      enc.integer(length, tail, value);
      sizer.integer(slength, stail, value);
    }
  }
}

TEST(PifsResidual, RowsCodedSizeIsTheEncodedSize) {
  // The rate control's size of a residual coded row by row is that of its bytes in the file.
  PifsRaster target, decoded;
  target.width = decoded.width = 77;
  target.height = decoded.height = 45;
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.f, 9.f);
  for (int y = 0; y < 45; ++y)
    for (int x = 0; x < 77; ++x) {
      decoded.values.push_back(float(128 + 50 * std::sin(x * 0.2) * std::cos(y * 0.15)));
      target.values.push_back(decoded.values.back() + noise(rng) * float(x % 20 < 12));
    }
  for (const double step : {0.5, 2.0, 6.0, 20.0}) {
    PifsResidualRows rows(77, 45, step);
    for (int j = 0; j < rows.rows(); ++j) rows.quantise(j, target, decoded);
    for (int j = 0; j < rows.rows(); ++j) rows.code(j);
    std::size_t size = 0;
    const PifsResidual residual = rows.finish(&size);
    ASSERT_NE(residual.step, 0) << "step " << step;
    EXPECT_EQ(size, encode_residual(residual, 77, 45).size()) << "step " << step;
  }
}

TEST(PifsFile, RoundTripsBytesAndFiles) {
  for (bool residual : {false, true}) {
  const PifsCode code = sample_code(residual);
  const std::vector<std::uint8_t> bytes = pifs_to_bytes(code);
  const PifsCode back = pifs_from_bytes(bytes.data(), bytes.size());
  ASSERT_EQ(back.planes.size(), code.planes.size());
  for (std::size_t k = 0; k < code.planes.size(); ++k) {
    ASSERT_EQ(back.planes[k].leaves.size(), code.planes[k].leaves.size());
    for (std::size_t i = 0; i < code.planes[k].leaves.size(); ++i) {
      const PifsLeaf &a = code.planes[k].leaves[i], &b = back.planes[k].leaves[i];
      EXPECT_TRUE(a.x == b.x && a.y == b.y && a.log_size == b.log_size && a.s == b.s && a.dc == b.dc);
      if (a.s != 0) {
        EXPECT_TRUE(a.isometry == b.isometry && a.dx == b.dx && a.dy == b.dy);
      }
    }
    EXPECT_EQ(back.planes[k].residual.step, code.planes[k].residual.step);
    EXPECT_EQ(back.planes[k].residual.coefficients, code.planes[k].residual.coefficients);
    EXPECT_EQ(code.planes[k].residual.step != 0, residual) << k;
  }
  EXPECT_EQ(pifs_to_bytes(back), bytes);
  const std::string path = ::testing::TempDir() + "/roundtrip.pifs";
  write_pifs(path, code);
  EXPECT_EQ(pifs_to_bytes(read_pifs(path)), bytes);
  std::remove(path.c_str());
  }
}

TEST(PifsFile, RefusesTruncatedAndCorruptFiles) {
  const std::vector<std::uint8_t> bytes = pifs_to_bytes(sample_code());
  for (std::size_t cut : {std::size_t(0), std::size_t(3), std::size_t(12), bytes.size() / 2, bytes.size() - 1}) {
    const std::string m = message_of(std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + cut));
    EXPECT_NE(m, "") << cut;
    EXPECT_NE(m.find("test.pifs"), std::string::npos) << m;
  }
  for (std::size_t at = 4; at < bytes.size(); at += 7) {
    std::vector<std::uint8_t> bad = bytes;
    bad[at] ^= 0x5A;
    EXPECT_NE(message_of(bad), "") << at;
  }
  std::vector<std::uint8_t> magic = bytes;
  magic[0] = 'X';
  EXPECT_NE(message_of(magic).find("not a PIFS file"), std::string::npos);
  std::vector<std::uint8_t> version = bytes;
  version[4] = 9;
  EXPECT_NE(message_of(version).find("version 9"), std::string::npos);
  EXPECT_THROW(read_pifs(::testing::TempDir() + "/missing.pifs"), FileError);
}

namespace {
std::uint32_t crc32(const std::uint8_t* data, std::size_t size) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) {
    c ^= data[i];
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
  }
  return c ^ 0xFFFFFFFFu;
}
}  // namespace

TEST(PifsFile, MutatedFilesWithValidChecksumsNeverCrash) {
  // Past the checksum every field is still checked: a mutation either reads as some valid code
  // (which then decodes) or is refused with InputError.
  for (bool residual : {false, true}) {
  const std::vector<std::uint8_t> bytes = pifs_to_bytes(sample_code(residual));
  std::mt19937 rng(11);
  int refused = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<std::uint8_t> bad = bytes;
    const int flips = 1 + int(rng() % 3);
    for (int f = 0; f < flips; ++f) bad[4 + rng() % (bad.size() - 8)] ^= std::uint8_t(1u << (rng() % 8));
    const std::uint32_t c = crc32(bad.data(), bad.size() - 4);
    for (int i = 0; i < 4; ++i) bad[bad.size() - 4 + i] = std::uint8_t(c >> (8 * i));
    try {
      const PifsCode code = pifs_from_bytes(bad.data(), bad.size(), "fuzz.pifs");
      if (code.width * code.height <= 512 * 512) (void)pifs_decode(code);
    } catch (const InputError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 100);
  }
}

TEST(PifsResidual, CodesAndRestoresWhatTheFractalCodeMisses) {
  // A 21×13 plane (blocks cut by both edges) against a flat decoded plane: the residual's bytes
  // round-trip exactly, and adding it back leaves at most the quantiser's error.
  std::mt19937 rng(5);
  PifsRaster target, decoded;
  target.width = decoded.width = 24;
  target.height = decoded.height = 16;
  target.values.resize(24 * 16);
  for (float& v : target.values) v = float(rng() % 256);
  decoded.values.assign(24 * 16, 128.f);
  const double step = 2.0;
  const PifsResidual r = residual_quantise(target, decoded, 21, 13, step);
  ASSERT_EQ(r.step, int(step * kResidualStepScale));
  const std::vector<std::uint8_t> bytes = encode_residual(r, 21, 13);
  const PifsResidual back = decode_residual(r.step, 21, 13, bytes.data(), bytes.size(), "test");
  EXPECT_EQ(back.coefficients, r.coefficients);
  PifsRaster restored = decoded;
  add_residual(back, 21, 13, 0, restored);
  double squared = 0;
  for (int y = 0; y < 13; ++y)
    for (int x = 0; x < 21; ++x) squared += std::pow(restored.row(y)[x] - target.row(y)[x], 2);
  EXPECT_LT(std::sqrt(squared / (21 * 13)), step * 0.5);  // uniform rounding error: step / sqrt(12) or less
  EXPECT_THROW(decode_residual(r.step, 21, 13, bytes.data(), bytes.size() - 1, "test"), InputError);
  EXPECT_TRUE(residual_quantise(target, target, 21, 13, step).coefficients.empty());
}
