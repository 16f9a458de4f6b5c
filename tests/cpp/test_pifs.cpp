// PIFS image compression (seed 3.3.2): exact constant images, re-encoding a known attractor,
// Baharav's pyramid consistent across scales, hierarchical = iterative, any size and channels,
// rate control, identical output for any thread count (encoding, and decoding large enough to split).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ifsforge/core/error.h"
#include "ifsforge/io/pifs_file.h"
#include "ifsforge/pifs/block_search.h"
#include "ifsforge/pifs/code_bytes.h"
#include "ifsforge/pifs/decoder.h"
#include "ifsforge/pifs/encoder.h"
#include "ifsforge/pifs/plane_coding.h"
#include "ifsforge/pifs/planes.h"
#include "pifs_test.h"

using namespace ifsforge;
using pifs_test::psnr;
using pifs_test::textured;
using pifs_test::expect_same_decode_on;

namespace {

Image average2x2(const Image& big) {
  Image out(big.width / 2, big.height / 2, big.channels);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < big.channels; ++c)
        out.at(x, y, c) = 0.25f * (big.at(2 * x, 2 * y, c) + big.at(2 * x + 1, 2 * y, c) +
                                   big.at(2 * x, 2 * y + 1, c) + big.at(2 * x + 1, 2 * y + 1, c));
  return out;
}

PifsDecodeOptions plain(double scale = 1.0) {
  PifsDecodeOptions o;
  o.scale = scale;
  o.deblock = false;
  o.zoom = PifsZoom::Fractal;
  return o;
}

/// A random PIFS on a 64×64 plane with 8×8 range cells: every cell maps some domain with |s| ≥ 1/2.
PifsCode random_code(unsigned seed) {
  PifsCode code;
  code.width = code.height = 64;
  code.channels = 1;
  code.min_log = code.max_log = 3;
  PifsPlane plane;
  plane.width = plane.height = 64;
  std::mt19937 rng(seed);
  const int domains = domain_count(64, 3);
  for (int y = 0; y < 64; y += 8)
    for (int x = 0; x < 64; x += 8) {
      PifsLeaf leaf;
      leaf.x = std::uint16_t(x);
      leaf.y = std::uint16_t(y);
      leaf.log_size = 3;
      const int s = int(rng() % 8) + 8;
      leaf.s = std::int8_t(rng() % 2 ? s : -s);
      leaf.dc = std::uint8_t(60 + rng() % 136);
      leaf.isometry = std::uint8_t(rng() % 8);
      leaf.dx = std::uint16_t(rng() % domains);
      leaf.dy = std::uint16_t(rng() % domains);
      plane.leaves.push_back(leaf);
    }
  code.planes.push_back(plane);
  return code;
}

}  // namespace

TEST(Pifs, ConstantImageRoundTripsExactly) {
  for (int channels : {1, 2}) {
    Image im(37, 53, channels);
    for (std::size_t i = 0; i < im.pixels.size(); ++i) im.pixels[i] = (i % channels ? 200.f : 77.f) / 255.f;
    const PifsCode code = pifs_encode(im);
    for (const PifsPlane& p : code.planes)
      for (const PifsLeaf& l : p.leaves) EXPECT_EQ(l.s, 0);
    const Image out = pifs_decode(code);
    ASSERT_EQ(out.pixels.size(), im.pixels.size());
    for (std::size_t i = 0; i < im.pixels.size(); ++i) ASSERT_EQ(out.pixels[i], im.pixels[i]) << i;
  }
}

TEST(Pifs, KnownAttractorReencodesAbove40dB) {
  const PifsCode truth = random_code(7);
  Image attractor = pifs_decode(truth, plain());
  for (float& v : attractor.pixels) v = std::round(v * 255.f) / 255.f;  // an 8-bit image
  PifsEncodeOptions o;
  o.min_block = 4;
  o.max_block = 8;
  o.quality = 1.0;
  const PifsCode code = pifs_encode(attractor, o);
  EXPECT_GT(psnr(pifs_decode(code, plain()), attractor), 40.0);
}

TEST(Pifs, PyramidLevelsAgree) {
  // φ commutes with the 2×2 mean, so the 2× decode averaged is the 1× decode (Baharav).
  PifsEncodeOptions o;
  o.ratio = 12;
  const PifsCode code = pifs_encode(textured(96, 80, 1), o);
  const Image one = pifs_decode(code, plain(1));
  const Image two = pifs_decode(code, plain(2));
  ASSERT_EQ(two.width, 192);
  EXPECT_GT(psnr(average2x2(two), one), 30.0);
  EXPECT_GT(psnr(average2x2(pifs_decode(code, plain(0.5))), pifs_decode(code, plain(0.25))), 30.0);
}

TEST(Pifs, HierarchicalMatchesIterativeReference) {
  const PifsCode code = random_code(3);
  PifsDecodeOptions iterative = plain(2);
  iterative.decoder = PifsDecoder::Iterative;
  iterative.iterations = 40;
  PifsDecodeOptions hierarchical = plain(2);
  hierarchical.iterations = 40;
  EXPECT_GT(psnr(pifs_decode(code, iterative), pifs_decode(code, hierarchical)), 45.0);
}

TEST(Pifs, SameBytesForAnyThreadCount) {
  const Image im = textured(150, 110, 3);
  PifsEncodeOptions o;
  o.ratio = 15;
  o.threads = 1;
  const auto one = pifs_to_bytes(pifs_encode(im, o));
  PifsDecodeOptions d;
  d.scale = 2;
  d.threads = 1;
  const Image a = pifs_decode(pifs_from_bytes(one.data(), one.size()), d);
  for (int threads : {2, 3, 7}) {
    o.threads = threads;
    const PifsCode code = pifs_encode(im, o);
    EXPECT_EQ(one, pifs_to_bytes(code)) << threads << " threads";
    d.threads = threads;
    EXPECT_EQ(a.pixels, pifs_decode(code, d).pixels) << threads << " threads";
  }
}

TEST(Pifs, LargeDecodeIsTheSameForAnyThreadCount) {
  // 2048×1536 pixels: the passes and the deblocking filter of a gray plane split, and the
  // conversion to RGB of a colour image.
  for (int channels : {1, 3}) {
    const PifsCode code = pifs_encode(textured(128, 96, channels), PifsEncodeOptions{});
    PifsDecodeOptions d;
    d.scale = 16;
    expect_same_decode_on(code, d, {2, 3}, std::to_string(channels) + " channels, ");
  }
}

TEST(Pifs, CanonicalOrientationIsTheSameForEveryView) {
  std::mt19937 rng(3);
  std::normal_distribution<float> normal;
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<float> block(16);
    for (float& v : block) v = normal(rng);
    BlockFeature f;
    ASSERT_TRUE(block_feature(block.data(), 4, 4, f));
    const Orientation o = canonical_orientation(f);
    const BlockFeature canonical = transform_feature(f, o.isometry, o.negate);
    for (int iso = 0; iso < 8; ++iso)
      for (bool negate : {false, true}) {
        const BlockFeature view = transform_feature(f, iso, negate);
        const Orientation v = canonical_orientation(view);
        EXPECT_EQ(transform_feature(view, v.isometry, v.negate), canonical);
        // The canonical view found from `view`, undone, gives `view` back through f's own turn.
        const int back = compose_isometry(o.isometry, inverse_isometry(v.isometry));
        EXPECT_EQ(transform_feature(f, back, negate), view);
      }
  }
  for (int a = 0; a < 8; ++a) {
    EXPECT_EQ(compose_isometry(a, inverse_isometry(a)), 0);
    EXPECT_EQ(compose_isometry(inverse_isometry(a), a), 0);
  }
}

TEST(Pifs, RatioControlsTheFileSize) {
  const Image im = textured(200, 120, 1);
  for (double ratio : {8.0, 20.0}) {
    PifsEncodeOptions o;
    o.ratio = ratio;
    const std::size_t size = pifs_to_bytes(pifs_encode(im, o)).size();
    const double target = 200.0 * 120 / ratio;
    EXPECT_LE(size, target);
    EXPECT_GE(size, 0.9 * target);
  }
  PifsEncodeOptions o;
  o.bytes = 10;
  EXPECT_THROW(pifs_encode(im, o), InputError);
}

TEST(Pifs, AnySizeAndChannels) {
  for (int channels : {1, 2, 3, 4}) {
    const Image im = textured(45, 71, channels);
    PifsEncodeOptions o;
    o.quality = 2;
    const PifsCode code = pifs_encode(im, o);
    EXPECT_EQ(code.planes.size(), std::size_t(channels));
    const Image out = pifs_decode(code);
    EXPECT_EQ(out.width, 45);
    EXPECT_EQ(out.height, 71);
    EXPECT_EQ(out.channels, channels);
    EXPECT_GT(psnr(out, im), channels >= 3 ? 27.0 : 30.0) << channels;
    PifsDecodeOptions d;
    d.width = 100;
    d.height = 33;
    const Image resized = pifs_decode(code, d);
    EXPECT_EQ(resized.width, 100);
    EXPECT_EQ(resized.height, 33);
  }
}

TEST(Pifs, TwoPixelRangeCellsRoundTripAndAddDetail) {
  const Image im = textured(96, 80, 1);
  PifsEncodeOptions o;
  o.quality = 0;  // split to the smallest cells
  o.min_block = 4;
  const PifsCode four = pifs_encode(im, o);
  o.min_block = 2;
  const PifsCode two = pifs_encode(im, o);
  EXPECT_EQ(two.min_log, 1);
  const auto bytes = pifs_to_bytes(two);
  EXPECT_EQ(pifs_to_bytes(pifs_from_bytes(bytes.data(), bytes.size())), bytes);
  EXPECT_GT(psnr(pifs_decode(two, plain()), im), psnr(pifs_decode(four, plain()), im) + 3.0);
  o.min_block = 0;  // automatic: a quality this fine buys 2×2 cells, a 50:1 budget does not
  EXPECT_EQ(pifs_encode(im, o).min_log, 1);
  o.ratio = 50;
  EXPECT_EQ(pifs_encode(im, o).min_log, 3);  // under a size target the residual's 8×8 blocks
  o.residual = false;
  EXPECT_EQ(pifs_encode(im, o).min_log, 2);
}

TEST(Pifs, RefusesBadOptions) {
  PifsEncodeOptions o;
  o.min_block = 6;
  EXPECT_THROW(pifs_encode(textured(32, 32, 1), o), InputError);
  o.min_block = 1;
  EXPECT_THROW(pifs_encode(textured(32, 32, 1), o), InputError);
  EXPECT_THROW(pifs_encode(Image(), PifsEncodeOptions{}), InputError);
  PifsDecodeOptions d;
  d.scale = -1;
  EXPECT_THROW(pifs_decode(random_code(1), d), InputError);
}

TEST(PifsChroma, HalvingErrorIsWhatAveragingTheChromaLoses) {
  // Gray has no chroma to lose.
  Image gray(8, 6, 3);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 3; ++c) gray.at(x, y, c) = float(x * 30 + y) / 255.f;
  EXPECT_LT(chroma_halving_error(gray), 1e-6);
  // Rows of pure red over rows of pure blue: each pixel's chroma is off by half the pair's
  // difference, which the inverse matrix turns into an RGB error of the same size on every pixel.
  Image rows(8, 6, 3);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      rows.at(x, y, 0) = y % 2 ? 0.f : 1.f;
      rows.at(x, y, 1) = 0.f;
      rows.at(x, y, 2) = y % 2 ? 1.f : 0.f;
    }
  const double dcb = ((128 + 0.5 * 255) - (128 - 0.168736 * 255)) / 2;
  const double dcr = ((128 - 0.081312 * 255) - (128 + 0.5 * 255)) / 2;
  const double r = 1.402 * dcr, g = -0.344136 * dcb - 0.714136 * dcr, b = 1.772 * dcb;
  EXPECT_NEAR(chroma_halving_error(rows, 2), (r * r + g * g + b * b) / 3, 1e-2);
  EXPECT_EQ(chroma_halving_error(rows, 1), chroma_halving_error(rows, 2));
}
