// Polar IFS (seed 3.3.3, Eq. 30-32): local contraction, files, chaos and prr, breeding.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ifsforge/core/error.h"
#include "ifsforge/design/breed.h"
#include "ifsforge/design/morph.h"
#include "ifsforge/io/ifs_json.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/render/renderer.h"
#include "algorithms_test.h"

using namespace ifsforge;
using ifsforge::algorithms_test::iou;

namespace {

PolarMap random_polar(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PolarMap m;
  m.center = {u(rng), u(rng)};
  m.k = 0.1 + 2.0 * (u(rng) + 1.0);
  for (double& f : m.f) f = u(rng);
  for (double& g : m.g) g = 3.0 * u(rng);
  m.winding = static_cast<int>(std::lround(2.0 * u(rng)));
  return m;
}

/// Three spiralling polar maps: a locally contractive system with a 2D attractor.
Ifs spirals() {
  std::vector<PolarMap> maps(3);
  const double centres[3][2] = {{0.0, 0.8}, {-0.7, -0.4}, {0.7, -0.4}};
  for (int i = 0; i < 3; ++i) {
    maps[i].center = {centres[i][0], centres[i][1]};
    maps[i].k = 1.2;
    maps[i].f = {-0.2, 0.3, 0.25 * i, -0.2, 0.15, 0.0};
    maps[i].g = {0.9 + 0.4 * i, 0.6, 0.1, 0.0};
  }
  return polar_ifs("spirals", maps);
}

std::string polar_document(const std::string& map, const std::string& extra = "") {
  return R"({"format": "ifsforge/1", "maps": [{"polar": )" + map +
         R"(}, {"matrix": [[0.5, 0], [0, 0.5]], "offset": [0.5, 0]}])" + extra + "}";
}

}  // namespace

TEST(Polar, Eq30HoldsWithTheReportedRatio) {
  std::mt19937 rng(30);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  for (int trial = 0; trial < 20; ++trial) {
    const PolarMap m = random_polar(rng);
    const double s = m.contraction();
    ASSERT_LT(s, 1.0);
    for (int i = 0; i < 10000; ++i) {
      const double M[2] = {m.center[0] + u(rng), m.center[1] + u(rng)};
      double W[2];
      m.apply(M, W);
      const double before = std::hypot(M[0] - m.center[0], M[1] - m.center[1]);
      const double after = std::hypot(W[0] - m.center[0], W[1] - m.center[1]);
      ASSERT_LT(after, s * before) << "trial " << trial << " point " << i;
    }
  }
}

TEST(Polar, CentreIsFixedAndSystemIsLocallyContractive) {
  const Ifs ifs = spirals();
  EXPECT_EQ(ifs.classify(), Classification::LocallyContractive);
  for (std::size_t i = 0; i < ifs.size(); ++i) {
    const PolarMap& m = *ifs.polar_maps()[i];
    Point p{};
    p[0] = m.center[0];
    p[1] = m.center[1];
    const Point q = ifs.apply(i, p);
    EXPECT_EQ(q[0], p[0]);
    EXPECT_EQ(q[1], p[1]);
    EXPECT_DOUBLE_EQ(ifs.spatial_contraction_factors()[i], m.contraction());  // the shadow's s_i
  }
}

TEST(Polar, JsonRoundTripIsExact) {
  const std::string text = R"({"format": "ifsforge/1", "layout": "xy+k", "maps": [
    {"polar": {"center": [0.1, -0.3], "k": 1.7, "F": [-0.3, 0.2, 0.1, 0.123456789012345, 0, 1e-7],
               "G": [1.5, -0.25, 0.0, 0.3], "winding": -1}, "channels": [[0, 0, 0.5, 0.25]], "probability": 2},
    {"matrix": [[0.5, 0, 0], [0, 0.5, 0], [0, 0, 0.5]], "offset": [0.5, 0.2, 0.5], "probability": 1}]})";
  const Ifs a = parse_ifs_json(text, "mixed.json");
  ASSERT_TRUE(a.polar_maps()[0].has_value());
  EXPECT_FALSE(a.polar_maps()[1].has_value());
  const Ifs b = parse_ifs_json(to_ifs_json(a), "again.json");
  EXPECT_EQ(to_ifs_json(a), to_ifs_json(b));
  EXPECT_EQ(*a.polar_maps()[0], *b.polar_maps()[0]);
  EXPECT_EQ(a.probabilities(), b.probabilities());
  EXPECT_EQ(a.map(0).matrix(), b.map(0).matrix());
  EXPECT_EQ(a.map(0).offset(), b.map(0).offset());
  EXPECT_EQ(b.polar_maps()[0]->f[3], 0.123456789012345);
}

TEST(Polar, BadInputNamesTheField) {
  auto error_of = [](const std::string& text) {
    try {
      parse_ifs_json(text, "bad.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string ok = R"({"center": [0, 0], "k": 1, "F": [0, 0, 0, 0, 0, 0], "G": [0, 0, 0, 0]})";
  EXPECT_EQ(error_of(polar_document(ok)), "no error");
  const std::pair<std::string, std::string> cases[] = {
      {R"({"center": [0, 0], "k": 0, "F": [0,0,0,0,0,0], "G": [0,0,0,0]})", "/maps/0/polar/k"},
      {R"({"center": [0, 0], "k": -2, "F": [0,0,0,0,0,0], "G": [0,0,0,0]})", "/maps/0/polar/k"},
      {R"({"center": [0, 0], "k": 1, "F": [0,0,0,0,0], "G": [0,0,0,0]})", "/maps/0/polar/F: expected 6 numbers"},
      {R"({"center": [0, 0], "k": 1, "F": [0,0,0,0,0,0], "G": [0,0,0]})", "/maps/0/polar/G: expected 4 numbers"},
      {R"({"center": [0], "k": 1, "F": [0,0,0,0,0,0], "G": [0,0,0,0]})", "/maps/0/polar/center"},
      {R"({"k": 1, "F": [0,0,0,0,0,0], "G": [0,0,0,0]})", "needs 'center'"},
      {R"({"center": [0, 0], "k": 1, "F": [0,0,0,0,0,0], "G": [0,0,0,0], "winding": 0.5})", "/maps/0/polar/winding"},
      {R"({"center": [0, 0], "k": 1e6, "F": [50,0,0,0,0,0], "G": [0,0,0,0]})", "rounds to 1"},
      {R"({"center": [0, 0], "k": 1, "F": [0,0,0,0,0,0], "G": [0,0,0,0], "h": 1})", "/maps/0/polar/h: unknown field"},
  };
  for (const auto& [map, message] : cases)
    EXPECT_NE(error_of(polar_document(map)).find(message), std::string::npos) << map << " -> " << error_of(polar_document(map));
  EXPECT_NE(error_of(polar_document(ok, R"(, "transitions": [[1, 1], [1, 1]])")).find("polar"), std::string::npos);
  EXPECT_NE(error_of(R"({"layout": "xyz", "maps": [{"polar": )" + ok + "}]}").find("not 2D"), std::string::npos);
  // A PolarMap built in code is checked as the file's is.
  PolarMap nan;
  nan.k = std::nan("");
  EXPECT_THROW(polar_ifs("nan", {nan}), InputError);
}

TEST(Polar, OtherAlgorithmsRefuseWithTheAlternatives) {
  const Ifs ifs = spirals();
  RenderOptions o;
  o.width = o.height = 32;
  for (const Renderer* r : renderers()) {
    if (r->name() == "chaos" || r->name() == "prr") continue;
    try {
      r->render(ifs, o);
      ADD_FAILURE() << r->name() << " rendered a polar system";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("does not render polar maps"), std::string::npos) << r->name() << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("use chaos or prr"), std::string::npos) << r->name();
    }
  }
  // Code that composes or interpolates the affine maps would use the shadows: it refuses too.
  EXPECT_THROW(morph(ifs, ifs, 0.5), InputError);
}

TEST(Polar, ChaosAndPrrAgree) {
  const Ifs ifs = spirals();
  RenderOptions o;
  o.width = o.height = 256;
  o.binary = true;
  const Raster prr = renderer("prr").render(ifs, o);
  // The faint rims of this overlapping system take chaos long to fill (more points still add
  // pixels): 2^24 points.
  o.iterations = std::uint64_t(1) << 24;
  const Raster chaos = renderer("chaos").render(ifs, o);
  EXPECT_GT(chaos.covered(), 20000u);
  EXPECT_GE(iou(chaos, prr), 0.9);
  // The measure too: prr's leaves carry the products of the probabilities, which sum to 1.
  o.binary = false;
  const Raster measure = renderer("prr").render(ifs, o);
  double total = 0.0;
  for (float v : measure.density) total += v;
  EXPECT_NEAR(total, 1.0, 0.02);
}

TEST(Polar, OutputDoesNotDependOnThreads) {
  const Ifs ifs = spirals();
  for (const char* name : {"chaos", "prr"}) {
    RenderOptions o;
    o.width = o.height = 128;
    o.threads = 1;
    const Raster one = renderer(name).render(ifs, o);
    o.threads = 2;
    const Raster two = renderer(name).render(ifs, o);
    EXPECT_EQ(one.density, two.density) << name;
  }
}

TEST(Polar, BreedIsDeterministicAndLocallyContractive) {
  BreedOptions o;
  o.count = 4;
  o.seed = 11;
  const std::vector<Ifs> a = breed(o), b = breed(o);
  ASSERT_EQ(a.size(), 4u);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(to_ifs_json(a[k]), to_ifs_json(b[k]));
    EXPECT_EQ(a[k].classify(), Classification::LocallyContractive);
    for (const auto& m : a[k].polar_maps()) {
      ASSERT_TRUE(m.has_value());
      EXPECT_LE(m->contraction(), 0.9);
      for (int i = 0; i < 1000; ++i) {
        const double M[2] = {u(rng), u(rng)};
        double W[2];
        m->apply(M, W);
        EXPECT_LT(std::hypot(W[0] - m->center[0], W[1] - m->center[1]),
                  m->contraction() * std::hypot(M[0] - m->center[0], M[1] - m->center[1]));
      }
    }
  }
  o.seed = 12;
  EXPECT_NE(to_ifs_json(breed(o)[0]), to_ifs_json(a[0]));
}
