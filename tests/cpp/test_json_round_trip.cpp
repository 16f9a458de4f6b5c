// A system written to JSON and read back is the same system: the same probabilities (written at
// round-trip precision, normalised as a fixed point), so every renderer draws the same maps and
// the image is the same bytes.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/io/ifs_json.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {
namespace {

Raster chaos(const Ifs& ifs) {
  RenderOptions o;
  o.width = o.height = 128;
  o.iterations = 400'000;
  o.threads = 2;
  return renderer("chaos").render(ifs, o);
}

TEST(JsonRoundTrip, EverySampleSystemRendersTheSameBytes) {
  int compared = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(IFSFORGE_SOURCE_DIR) + "/samples/systems")) {
    if (entry.path().extension() != ".json") continue;
    Ifs direct;
    try {
      direct = read_ifs_json(entry.path().string());
      renderer("chaos").require_handles(direct);
    } catch (const InputError&) {
      continue;  // a scene or terrain file, or a system random iteration does not draw
    }
    const std::string name = entry.path().filename().string();
    const Ifs again = parse_ifs_json(to_ifs_json(direct), name);
    EXPECT_EQ(direct.probabilities(), again.probabilities()) << name;
    EXPECT_EQ(to_ifs_json(direct), to_ifs_json(again)) << name;
    const Raster a = chaos(direct), b = chaos(again);
    EXPECT_EQ(a.density, b.density) << name;
    EXPECT_EQ(a.channels, b.channels) << name;
    EXPECT_EQ(a.depth, b.depth) << name;
    ++compared;
  }
  EXPECT_GE(compared, 20);
}

TEST(JsonRoundTrip, NormalisingProbabilitiesIsAFixedPoint) {
  const std::vector<AffineMap> maps(3, AffineMap(2, {0.5, 0, 0, 0.5}, {0, 0}));
  const Ifs once("thirds", ChannelLayout("xy"), maps, {1, 1, 1});
  const Ifs twice("thirds", ChannelLayout("xy"), maps, once.probabilities());
  EXPECT_EQ(once.probabilities(), twice.probabilities());
  const Ifs tenths("tenths", ChannelLayout("xy"), maps, {0.1, 0.2, 0.7});
  const Ifs again("tenths", ChannelLayout("xy"), maps, tenths.probabilities());
  EXPECT_EQ(tenths.probabilities(), again.probabilities());
}

}  // namespace
}  // namespace ifsforge
