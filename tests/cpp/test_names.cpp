// One table of names per enum (core/names.h): every name parses back to its value, and a wrong
// name is refused with the setting's name and every accepted name.
#include <gtest/gtest.h>

#include "ifsforge/core/names.h"
#include "ifsforge/volume/volume.h"
#include "ifsforge/volume/volume_renderer.h"

namespace ifsforge {
namespace {

template <typename E>
void expect_round_trip() {
  for (const auto& v : EnumNames<E>::values) {
    EXPECT_STREQ(name_of(v.value), v.name);
    EXPECT_EQ(parse_name<E>(v.name), v.value);
  }
}

TEST(EnumNames, EveryNameRoundTrips) {
  expect_round_trip<VolumeDensity>();
  expect_round_trip<ColorScale>();
  expect_round_trip<EscapeNorm>();
  EXPECT_EQ(names_of<VolumeDensity>(), (std::vector<std::string>{"binary", "hits", "measure"}));
}

TEST(EnumNames, UnknownNameListsTheChoices) {
  try {
    parse_name<VolumeDensity>("mass");
    FAIL() << "accepted 'mass'";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "unknown density 'mass'; choose one of: binary, hits, measure");
  }
  try {
    parse_name<ColorScale>("Auto", "--color-scale");
    FAIL() << "accepted 'Auto' (names are case-sensitive)";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "unknown --color-scale 'Auto'; choose one of: auto, range, clamp");
  }
}

}  // namespace
}  // namespace ifsforge
