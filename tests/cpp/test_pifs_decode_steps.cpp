// The encoder's staged 1× decode (cpp/src/pifs/decode_steps.h): whatever order its parts run in
// within a stage, the raster is decode_plane's at 1× deblocked, bit for bit, so the residual
// the encoder codes against it is the one the decoder adds to.
#include <gtest/gtest.h>

#include <string>

#include "../../cpp/src/pifs/decode_steps.h"
#include "ifsforge/pifs/deblock.h"
#include "ifsforge/pifs/decoder.h"
#include "ifsforge/pifs/encoder.h"
#include "pifs_test.h"

using namespace ifsforge;

TEST(PifsDecodeSteps, PartsInAnyOrderGiveTheDeblockedDecode) {
  struct Case {
    int width, height, channels, min_block;
    double ratio;
  };
  // Smallest cells of 2, 4 and 8 pixels (one, two and three doublings after the fixed point),
  // planes of whole and padded blocks, half-size chroma.
  for (const Case& c : {Case{96, 64, 1, 2, 6}, Case{100, 70, 1, 4, 12}, Case{160, 120, 3, 8, 20}}) {
    PifsEncodeOptions o;
    o.min_block = c.min_block;
    o.ratio = c.ratio;
    const PifsCode code = pifs_encode(pifs_test::textured(c.width, c.height, c.channels), o);
    for (std::size_t k = 0; k < code.planes.size(); ++k) {
      const PifsPlane& plane = code.planes[k];
      PifsRaster expected = decode_plane(code, plane, 0, PifsDecoder::Hierarchical, 0, 1);
      deblock(code, plane, 0, expected, 1);
      PlaneDecodeSteps steps(code, plane, 256);  // parts of 256 pixels: many parts in a small plane
      const std::vector<std::size_t> stages = steps.stages();
      ASSERT_EQ(stages.size(), std::size_t(code.min_log) + 2) << "the doublings, then two deblocking passes";
      EXPECT_GT(stages.back(), 8u);
      // Each stage's parts last to first, and odd parts before even ones.
      for (std::size_t s = 0; s < stages.size(); ++s)
        for (int odd = 1; odd >= 0; --odd)
          for (std::size_t i = stages[s]; i-- > 0;)
            if (int(i % 2) == odd) steps.run(s, i);
      const std::string what = std::to_string(c.width) + "x" + std::to_string(c.height) + ", plane " + std::to_string(k);
      EXPECT_EQ(steps.raster().width, expected.width) << what;
      EXPECT_EQ(steps.raster().height, expected.height) << what;
      EXPECT_TRUE(steps.raster().values == expected.values) << what;
    }
  }
}
