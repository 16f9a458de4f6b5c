// File formats: JSON round trip and errors, the Fractint importer, PNG round trip, atomic writes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "ifsforge/core/default_threads.h"
#include "ifsforge/core/error.h"
#include "ifsforge/io/fractint.h"
#include "ifsforge/io/ifs_json.h"
#include "ifsforge/io/png.h"

using namespace ifsforge;

namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* kLibrary = R"(; a library with comments
fern {   ; the Barnsley fern
  0     0    0    .16  0  0     .01
  .85  .04 -.04  .85   0  1.6   .85
  .2  -.26  .23  .22   0  1.6   .07
 -.15  .28  .26  .24   0  .44   .07
}
comma_triangle {
 0.5, 0, 0, 0.5, 0, 0, 1
	0.5,	0,	0,	0.5,	0.5,	0,	1   ; tabs and commas
 0.5, 0, 0, 0.5, 0.25, 0.5, 1 }
3dtetra (3D) {
 .5 0 0 0 .5 0 0 0 .5  0  0  0 .25
 .5 0 0 0 .5 0 0 0 .5 .5  0  0 .25
 .5 0 0 0 .5 0 0 0 .5  0 .5  0 .25
 .5 0 0 0 .5 0 0 0 .5  0  0 .5 .25
}
)";

}  // namespace

TEST(Fractint, ReadsEveryEntry) {
  const auto systems = parse_fractint(kLibrary, "lib.ifs");
  ASSERT_EQ(systems.size(), 3u);
  EXPECT_EQ(systems[0].name(), "fern");
  EXPECT_EQ(systems[0].size(), 4u);
  EXPECT_DOUBLE_EQ(systems[0].map(1).a(0, 1), 0.04);   // b
  EXPECT_DOUBLE_EQ(systems[0].map(1).a(1, 0), -0.04);  // c
  EXPECT_DOUBLE_EQ(systems[0].map(1).b(1), 1.6);       // f
  EXPECT_NEAR(systems[0].probabilities()[1], 0.85, 1e-12);
  EXPECT_EQ(systems[1].name(), "comma_triangle");
  EXPECT_DOUBLE_EQ(systems[1].map(2).b(0), 0.25);
  EXPECT_EQ(systems[2].dim(), 3);
  EXPECT_DOUBLE_EQ(systems[2].map(3).b(2), 0.5);  // l
  EXPECT_DOUBLE_EQ(systems[2].map(0).a(2, 2), 0.5);  // i
}

TEST(Fractint, ErrorsNameFileEntryAndLine) {
  const std::string e = error_of([] { parse_fractint("good { 1 0 0 1 0 0 1 }\nbad {\n .5 0 0 .5 0 0\n}\n", "f.ifs"); });
  EXPECT_NE(e.find("f.ifs:3"), std::string::npos) << e;
  EXPECT_NE(e.find("'bad'"), std::string::npos) << e;
  EXPECT_NE(e.find("7 numbers, found 6"), std::string::npos) << e;
  EXPECT_NE(error_of([] { parse_fractint("x {\n .5 0 0 .5 0 zero 1\n}", "f.ifs"); }).find("expected a number"), std::string::npos);
  EXPECT_NE(error_of([] { parse_fractint("x {\n .5 0 0 .5 0 0 0\n}", "f.ifs"); }).find("positive"), std::string::npos);
  EXPECT_NE(error_of([] { parse_fractint("x {\n .5 0 0 .5 0 0 1\n", "f.ifs"); }).find("closing"), std::string::npos);
  EXPECT_NE(error_of([] { parse_fractint("x (3D) {\n .5 0 0 .5 0 0 1\n}", "f.ifs"); }).find("13 numbers"), std::string::npos);
}

TEST(Json, RoundTrip) {
  const auto fern = parse_fractint(kLibrary).front();
  const Ifs back = parse_ifs_json(to_ifs_json(fern));
  ASSERT_EQ(back.size(), fern.size());
  for (std::size_t i = 0; i < fern.size(); ++i) {
    EXPECT_EQ(back.map(i).matrix(), fern.map(i).matrix());
    EXPECT_EQ(back.map(i).offset(), fern.map(i).offset());
    EXPECT_DOUBLE_EQ(back.probabilities()[i], fern.probabilities()[i]);
  }
}

TEST(Json, ParametersAndChannels) {
  const Ifs s = parse_ifs_json(R"({"format": "ifsforge/1", "layout": "xy+gray", "probabilities": "uniform",
    "maps": [{"scale": 0.5, "rotation": 90, "translation": [1, 0], "channels": [[0, 0, 0.5, 0.25]]},
             {"scale": [0.5, 0.5], "translation": [0, 0], "channels": [[0, 0, 0.5, 0]]}]})");
  EXPECT_EQ(s.dim(), 3);
  EXPECT_NEAR(s.map(0).a(1, 0), 0.5, 1e-15);
  EXPECT_NEAR(s.map(0).a(0, 1), -0.5, 1e-15);
  EXPECT_DOUBLE_EQ(s.map(0).a(2, 2), 0.5);
  EXPECT_DOUBLE_EQ(s.map(0).b(2), 0.25);
  EXPECT_DOUBLE_EQ(s.probabilities()[0], 0.5);
}

TEST(Json, ErrorsNameThePlace) {
  EXPECT_NE(error_of([] { parse_ifs_json("{\n \"maps\": [\n  {\"matrix\": [[1, 0] [0, 1]]}\n]}", "s.json"); }).find("s.json:3:"),
            std::string::npos);
  const std::string e = error_of([] {
    parse_ifs_json(R"({"maps": [{"matrix": [[0.5, 0], [0, 0.5]], "offset": [0, 0]}, {"matrix": [[0.5, "a"], [0, 0.5]], "offset": [0, 0]}]})", "s.json");
  });
  EXPECT_NE(e.find("/maps/1/matrix/0/1"), std::string::npos) << e;
  EXPECT_NE(error_of([] { parse_ifs_json(R"({"maps": [{"matrix": [[0.5, 0, 0], [0, 0.5, 0]], "offset": [0, 0]}]})"); }).find("/maps/0/matrix/0"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_ifs_json(R"({"maps": [{"matrix": [[0.5, 0], [0, 0.5]], "offset": [0, 0], "probability": -1}]})"); }).find("probability"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_ifs_json(R"({"format": "ifsforge/9", "maps": []})"); }).find("unsupported"), std::string::npos);
  EXPECT_NE(error_of([] { parse_ifs_json(R"({"maps": [], "colour": 1})"); }).find("/colour"), std::string::npos);
  EXPECT_NE(error_of([] { parse_ifs_json(R"({"maps": [{"matrix": [[1e999, 0], [0, 0.5]], "offset": [0, 0]}]})"); }), "");
}

TEST(Png, RoundTrip16And8Bit) {
  Image image(5, 3, 4);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<float>(i % 17) / 16.0f;
  const std::string path = ::testing::TempDir() + "ifsforge_png_test.png";
  for (int depth : {8, 16}) {
    write_png(path, image, depth);
    const Image back = read_png(path);
    ASSERT_EQ(back.width, 5);
    ASSERT_EQ(back.height, 3);
    ASSERT_EQ(back.channels, 4);
    const float step = depth == 8 ? 1.0f / 255 : 1.0f / 65535;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) EXPECT_NEAR(back.pixels[i], image.pixels[i], step * 0.51f);
  }
  std::remove(path.c_str());
}

TEST(Png, FailuresLeaveNoFile) {
  EXPECT_THROW(write_png("/nonexistent-folder/x.png", Image(2, 2, 1)), FileError);
  const std::string bogus = ::testing::TempDir() + "ifsforge_not_a.png";
  std::ofstream(bogus) << "hello";
  EXPECT_THROW(read_png(bogus), InputError);
  std::remove(bogus.c_str());
  // Nothing named like a temporary is left behind.
  const std::string target = ::testing::TempDir() + "ifsforge_bad_depth.png";
  EXPECT_THROW(write_png(target, Image(2, 2, 1), 12), InputError);
  EXPECT_NE(access(target.c_str(), F_OK), 0);
}

TEST(Png, StripsJoinIntoOneStreamWhateverTheThreads) {
  // 700 x 500 RGBA at 16 bits: 2.8 MB of filtered rows, eleven deflate strips.
  Image image(700, 500, 4);
  std::uint32_t state = 12345;
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    state = state * 1664525u + 1013904223u;
    const int x = static_cast<int>(i / 4 % 700), y = static_cast<int>(i / 2800);
    image.pixels[i] = i % 7 == 0 ? float(state >> 8) / float(1 << 24) : float((x * 3 + y * 5) % 997) / 996.0f;
  }
  const std::string one = ::testing::TempDir() + "ifsforge_png_one.png";
  const std::string three = ::testing::TempDir() + "ifsforge_png_three.png";
  set_default_threads(1);
  write_png(one, image, 16);
  set_default_threads(3);
  write_png(three, image, 16);
  set_default_threads(0);
  std::ifstream a(one, std::ios::binary), b(three, std::ios::binary);
  const std::string bytes_one((std::istreambuf_iterator<char>(a)), {}), bytes_three((std::istreambuf_iterator<char>(b)), {});
  EXPECT_EQ(bytes_one, bytes_three);
  EXPECT_GT(bytes_one.size(), 100000u);
  const Image back = read_png(one);  // libpng checks every chunk's CRC and the stream's Adler-32
  ASSERT_EQ(back.pixels.size(), image.pixels.size());
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    ASSERT_EQ(std::lround(back.pixels[i] * 65535.0), std::lround(image.pixels[i] * 65535.0)) << i;
  std::remove(one.c_str());
  std::remove(three.c_str());
}
