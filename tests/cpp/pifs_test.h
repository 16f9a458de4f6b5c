#pragma once
// Shared by the PIFS suites: a smooth picture with detail at several scales and a step down the
// middle, PSNR on [0, 1] values, and the check that a decode is the same on any thread count.
#include <gtest/gtest.h>

#include <cmath>

#include <initializer_list>
#include <string>

#include "ifsforge/core/image.h"
#include "ifsforge/pifs/decoder.h"

namespace ifsforge::pifs_test {

inline Image textured(int w, int h, int channels) {
  Image im(w, h, channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c)
        im.at(x, y, c) = float(0.5 + 0.3 * std::sin(x / (7.0 + c)) * std::cos(y / 11.0) +
                               0.12 * std::sin((x + 2 * y) / 3.0 + c) + (x > w / 2 ? 0.05 : -0.05));
  return im;
}

inline double psnr(const Image& a, const Image& b) {
  EXPECT_EQ(a.pixels.size(), b.pixels.size());
  double se = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) se += std::pow(double(a.pixels[i]) - b.pixels[i], 2);
  const double mse = se / a.pixels.size();
  return mse == 0 ? 1e9 : 10 * std::log10(1.0 / mse);
}

// Decodes with `d` on one thread, then on each of `counts`, and expects the same pixels.
inline void expect_same_decode_on(const PifsCode& code, PifsDecodeOptions d, std::initializer_list<int> counts,
                                  const std::string& what = "") {
  d.threads = 1;
  const Image one = pifs_decode(code, d);
  for (int threads : counts) {
    d.threads = threads;
    EXPECT_EQ(one.pixels, pifs_decode(code, d).pixels) << what << threads << " threads";
  }
}

}  // namespace ifsforge::pifs_test
