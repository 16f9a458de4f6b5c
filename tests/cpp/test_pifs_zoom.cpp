// The zoom post-filter of a magnified PIFS decode (zoom.h): the bicubic upscale keeps constants
// and reproduces straight ramps, the filtered decode averages back to the 1× decode, a constant
// image stays exactly constant at every scale, and the output is the same for any thread count.
#include <gtest/gtest.h>

#include <cmath>

#include "ifsforge/pifs/decoder.h"
#include "ifsforge/pifs/encoder.h"
#include "ifsforge/pifs/zoom.h"
#include "pifs_test.h"

using namespace ifsforge;
using pifs_test::psnr;
using pifs_test::textured;
using pifs_test::expect_same_decode_on;

namespace {

/// The f×f means of `big` (f = big.width / width).
Image averaged(const Image& big, int width, int height) {
  const int f = big.width / width;
  Image out(width, height, big.channels);
  for (int y = 0; y < big.height; ++y)
    for (int x = 0; x < big.width; ++x)
      for (int c = 0; c < big.channels; ++c) out.at(x / f, y / f, c) += big.at(x, y, c) / float(f * f);
  return out;
}

}  // namespace

TEST(PifsZoom, BicubicKeepsConstantsAndReproducesRamps) {
  PifsRaster r{9, 7, std::vector<float>(63)};
  for (int log_factor : {1, 2, 3}) {
    const int f = 1 << log_factor;
    std::fill(r.values.begin(), r.values.end(), 0.3f);
    for (float v : upscale_bicubic(r, log_factor).values) ASSERT_NEAR(v, 0.3f, 1e-6f);
    // A ramp along x: away from the repeated edges, output pixel i·f + p lies at source i + (p + ½)/f − ½.
    for (int y = 0; y < r.height; ++y)
      for (int x = 0; x < r.width; ++x) r.row(y)[x] = 2.f * x - 1.f;
    const PifsRaster up = upscale_bicubic(r, log_factor, 3);
    for (int y = 0; y < up.height; ++y)
      for (int X = 2 * f; X < up.width - 2 * f; ++X)
        ASSERT_NEAR(up.row(y)[X], 2.0 * ((X + 0.5) / f - 0.5) - 1.0, 1e-5) << f << " " << X;
  }
}

TEST(PifsZoom, MagnifiedDecodeAveragesBackToTheNativeDecode) {
  // Full-size planes only: half-size chroma at 1× is itself a magnified fractal decode.
  for (int channels : {1, 2}) {
    PifsEncodeOptions o;
    o.ratio = 10;
    const PifsCode code = pifs_encode(textured(96, 64, channels), o);
    const Image one = pifs_decode(code);
    for (double scale : {2.0, 4.0}) {
      PifsDecodeOptions d;
      d.scale = scale;
      const Image big = pifs_decode(code, d);
      EXPECT_GT(psnr(averaged(big, 96, 64), one), 40.0) << channels << " channels, " << scale << "x";
      d.zoom = PifsZoom::Fractal;
      EXPECT_NE(big.pixels, pifs_decode(code, d).pixels);
    }
  }
}

TEST(PifsZoom, ConstantImageStaysConstantAtEveryScale) {
  for (int channels : {1, 3}) {
    Image im(40, 24, channels);
    for (std::size_t i = 0; i < im.pixels.size(); ++i) im.pixels[i] = float(60 + 50 * (i % channels)) / 255.f;
    const PifsCode code = pifs_encode(im);
    const Image one = pifs_decode(code);  // colour: the YCbCr round trip rounds
    for (double scale : {2.0, 3.0, 4.0}) {
      PifsDecodeOptions d;
      d.scale = scale;
      const Image big = pifs_decode(code, d);
      for (std::size_t i = 0; i < big.pixels.size(); ++i)
        ASSERT_NEAR(big.pixels[i], one.pixels[i % channels], 1e-5f) << channels << " channels, " << i;
    }
  }
}

TEST(PifsZoom, SameOutputForAnyThreadCount) {
  // 2048×1200 pixels at 2× (the setting with a back-projection step): the filter's passes split.
  // Larger scales go through Pifs.LargeDecodeIsTheSameForAnyThreadCount.
  PifsEncodeOptions o;
  o.ratio = 50;
  const PifsCode code = pifs_encode(textured(1024, 600, 1), o);
  PifsDecodeOptions d;
  d.scale = 2;
  expect_same_decode_on(code, d, {2, 5});
}
