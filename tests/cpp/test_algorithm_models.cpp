// The model extensions of the rendering catalogue (recurrent IFS, super IFS, condensation
// sets), the address algorithms (string rewriting, TSA), image-based iteration, and the checks
// of renderer parameters and JSON extensions.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "ifsforge/core/error.h"
#include "ifsforge/io/ifs_json.h"
#include "ifsforge/io/png.h"
#include "ifsforge/model/recurrent.h"
#include "ifsforge/model/super_ifs.h"
#include "ifsforge/render/box_counting.h"
#include "ifsforge/render/color_bounds.h"
#include "ifsforge/render/image_based.h"
#include "ifsforge/render/minimal_plotting.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/render/self_congruent.h"
#include "ifsforge/render/string_rewriting.h"
#include "ifsforge/render/tone_map.h"
#include "ifsforge/vector/addresses.h"
#include "algorithms_test.h"

using namespace ifsforge;
using namespace ifsforge::algorithms_test;

TEST(Algorithms, RecurrentChainFacts) {
  const TransitionMatrix p(3, {0, 2, 2, 1, 0, 1, 1, 1, 0});
  const auto m = p.stationary();
  for (std::size_t j = 0; j < 3; ++j) {
    double v = 0;
    for (std::size_t i = 0; i < 3; ++i) v += m[i] * p(i, j);
    EXPECT_NEAR(v, m[j], 1e-12);  // m P = m
  }
  EXPECT_NEAR(m[0] + m[1] + m[2], 1.0, 1e-12);
  const TransitionMatrix r = p.reversed();
  for (std::size_t j = 0; j < 3; ++j) {
    double row = 0;
    for (std::size_t i = 0; i < 3; ++i) {
      row += r(j, i);
      EXPECT_NEAR(r(j, i), m[i] * p(i, j) / m[j], 1e-12);  // Eq. 73
    }
    EXPECT_NEAR(row, 1.0, 1e-12);
  }
  EXPECT_THROW(TransitionMatrix(2, {1, 0, 0, 1}), InputError);  // two separate chains
  EXPECT_THROW(TransitionMatrix(2, {1, -1, 0, 1}), InputError);
  EXPECT_THROW(TransitionMatrix(2, {0, 0, 1, 1}), InputError);
}

TEST(Algorithms, RecurrentSquaresHaveDimensionLogThreeOverLogTwo) {
  // Forbidding the opposite quadrant leaves 3 successors per map: box-counting dimension
  // log(spectral radius 3) / log 2, whichever algorithm follows the transitions.
  const Ifs ifs = sample("recurrent_squares");
  ASSERT_TRUE(ifs.recurrent());
  const Raster pd = renderer("probabilistic-domain").render(ifs, on_window(ifs, 512));
  EXPECT_NEAR(box_counting(pd, 2, 16).dimension, std::log(3.0) / std::log(2.0), 0.06);
  for (const char* name : {"chaos", "photocopy"}) {
    RenderOptions o = on_window(ifs, 512);
    if (std::string(name) == "photocopy") o.parameters["supersample"] = "2";
    EXPECT_GE(iou(renderer(name).render(ifs, o), pd), 0.9) << name;
  }
  // The same maps without transitions fill the square.
  Ifs plain = ifs;
  plain.set_transitions(TransitionMatrix());
  EXPECT_GT(renderer("prr").render(plain, on_window(plain, 128)).covered(), 0.9 * 128 * 128);
  // JSON keeps the matrix (and writes no map probabilities for it).
  const Ifs again = parse_ifs_json(to_ifs_json(ifs));
  EXPECT_EQ(again.transitions().values(), ifs.transitions().values());
  EXPECT_THROW(renderer("dia").render(ifs, on_window(ifs, 64)), InputError);
}

TEST(Algorithms, SuperfractalMembersAndSeeds) {
  const Ifs sf = sample("superfractal_pair");
  ASSERT_EQ(sf.super_ifs().members(), 2u);
  const Ifs again = parse_ifs_json(to_ifs_json(sf));
  EXPECT_EQ(again.super_ifs().sizes, sf.super_ifs().sizes);
  EXPECT_EQ(again.super_ifs().variability, 2);
  for (std::size_t i = 0; i < sf.size(); ++i) EXPECT_NEAR(again.probabilities()[i], sf.probabilities()[i], 1e-12);
  RenderOptions o = on_window(sf, 128);
  const Raster a = renderer("dia-s").render(sf, o);
  const Raster b = renderer("dia-s").render(sf, o);
  EXPECT_EQ(a.density, b.density);
  std::set<LargeVector<float>> breed;
  for (std::uint64_t seed = 0; seed < 4; ++seed) {
    o.seed = seed;
    breed.insert(renderer("dia-s").render(sf, o).density);
  }
  EXPECT_GT(breed.size(), 1u);  // the seed picks the member of the superfractal
  // An ordinary IFS is a one-member super IFS: DIA-S then is deterministic iteration.
  const Ifs fern = sample("barnsley_fern");
  EXPECT_EQ(renderer("dia-s").render(fern, on_window(fern, 128)).density,
            renderer("dia").render(fern, on_window(fern, 128)).density);
  // Members alone: each is the member's own attractor.
  EXPECT_EQ(super_member(sf, 1).size(), 3u);
}

TEST(Algorithms, CondensationSetsGrowIntoTheTree) {
  const Ifs tree = sample("condensation_tree");
  ASSERT_FALSE(tree.condensation().empty());
  const Ifs again = parse_ifs_json(to_ifs_json(tree));
  EXPECT_EQ(again.condensation().polygons, tree.condensation().polygons);
  const RenderOptions o = on_window(tree, 128);
  const auto frames = growth_frames(tree, o);
  ASSERT_GT(frames.size(), 5u);
  // Frame 0 is the trunk; every frame holds the one before; the last is the grown tree.
  const std::size_t trunk = frames[0].covered();
  EXPECT_GT(trunk, 20u);
  for (std::size_t k = 1; k < frames.size(); ++k)
    for (std::size_t p = 0; p < frames[k].density.size(); ++p)
      if (frames[k - 1].density[p] > 0.0f) {
        ASSERT_GT(frames[k].density[p], 0.0f) << "frame " << k;
      }
  const Raster dia = renderer("dia").render(tree, o);
  EXPECT_GE(iou(frames.back(), dia), 0.9);
  for (std::size_t p = 0; p < frames[0].density.size(); ++p)
    if (frames[0].density[p] > 0.0f) {
      EXPECT_GT(dia.density[p], 0.0f);  // C is in every iterate
    }
  EXPECT_THROW(renderer("eta").render(tree, o), InputError);
}

TEST(Algorithms, GrowthFromFixedPointsEndsAtTheMinimalPlottingSet) {
  // Without a condensation set the initiator is the fixed points' pixels: growing them
  // generation by generation closes them under the maps, exactly what the MPA queue does.
  const Ifs ifs = sample("crystal");
  const Raster grown = renderer("self-congruent").render(ifs, on_window(ifs, 200));
  const Raster mpa = renderer("mpa").render(ifs, on_window(ifs, 200));
  for (std::size_t p = 0; p < mpa.density.size(); ++p) ASSERT_EQ(grown.density[p] > 0.0f, mpa.density[p] > 0.0f);
}

TEST(Algorithms, StringRewritingWritesEveryAddress) {
  const Ifs ifs = sample("sierpinski_triangle");
  const auto strings = string_rewriting(ifs, 3, AddressSpelling::Seed);
  ASSERT_EQ(strings.size(), 27u);
  EXPECT_EQ(strings.front(), "w1w1w1");
  EXPECT_EQ(strings[1], "w2w1w1");  // the seed writes the new map in front
  EXPECT_EQ(std::set<std::string>(strings.begin(), strings.end()).size(), 27u);
  // At a fixed depth the strings applied to the start point are PRR's leaves.
  RenderOptions o = on_window(ifs, 256);
  o.depth = 8;
  EXPECT_EQ(iou(renderer("string-rewriting").render(ifs, o), renderer("prr").render(ifs, o)), 1.0);
  EXPECT_EQ(renderer("string-rewriting").render(ifs, o).points, 3u + 9 + 27 + 81 + 243 + 729 + 2187 + 6561);
}

TEST(Algorithms, StringRewritingIsOneProcedureSpelledTwoWays) {
  // 5.6: the new map goes in front, so the first symbol varies fastest.
  EXPECT_EQ(rewrite_map_strings({"a", "b"}, "-", 2), (std::vector<std::string>{"a-a", "b-a", "a-b", "b-b"}));
  EXPECT_EQ(rewrite_map_strings({"a", "b"}, "", 1), (std::vector<std::string>{"a", "b"}));
  EXPECT_THROW(rewrite_map_strings({"a"}, "", 0), InputError);
  // The renderer's "w2w1" and the vector layer's "1.0" are the same addresses in the same order.
  const Ifs ifs = sample("sierpinski_tetrahedron");
  const auto seed = string_rewriting(ifs, 3, AddressSpelling::Seed);
  const auto addresses = string_rewriting(ifs, 3);
  ASSERT_EQ(seed.size(), addresses.size());
  for (std::size_t i = 0; i < seed.size(); ++i) {
    std::string spelled;  // "1.0.3" -> "w2w1w4" (4 maps: one digit each)
    for (char digit : addresses[i])
      if (digit != '.') spelled += "w" + std::to_string(digit - '0' + 1);
    EXPECT_EQ(spelled, seed[i]);
  }
}

TEST(Algorithms, TesseralSynecdochePrunesByProbability) {
  const Ifs fern = sample("barnsley_fern");
  std::uint64_t previous = UINT64_MAX;
  std::size_t covered = SIZE_MAX;
  for (const char* pv : {"0", "1e-8", "1e-5", "1e-3"}) {
    const Raster r = renderer("tsa").render(fern, on_window(fern, 256, {{"threshold", pv}}));
    EXPECT_LE(r.points, previous) << pv;
    EXPECT_LE(r.covered(), covered) << pv;
    previous = r.points;
    covered = r.covered();
  }
  EXPECT_LT(covered, renderer("tsa").render(fern, on_window(fern, 256, {{"threshold", "0"}})).covered() * 0.9);
}

TEST(Algorithms, ImageBasedIterationsAndMass) {
  // Eq. 65 for diameters: copies of a 1024-pixel image shrink below a pixel after
  // log(1024) / log(2) = 10 halvings (plus one).
  EXPECT_EQ(image_based_iterations(sample("sierpinski_triangle"), 1024, 1024), 11);
  // Measure weights p_i / D_i (Eq. 64) keep the total mass of the image.
  const Ifs ifs = sample("sierpinski_triangle");
  // On one grid (supersample 1): the mass is counted in cells of that grid.
  RenderOptions o = on_window(ifs, 128, {{"weights", "measure"}, {"supersample", "1"}});
  o.window = Window{-0.5, -0.5, 1.5, 1.5};  // room around the attractor: nothing leaves
  const Raster r = renderer("ibr").render(ifs, o);
  double total = 0;
  for (float d : r.density) total += d;
  EXPECT_NEAR(total, 128.0 * 128.0, 0.01 * 128 * 128);
}

TEST(Algorithms, ParametersAreCheckedByName) {
  const Ifs ifs = sample("sierpinski_triangle");
  try {
    renderer("eta").render(ifs, on_window(ifs, 32, {{"nrom", "linear"}}));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'nrom'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("norm"), std::string::npos);  // lists the right names
  }
  EXPECT_THROW(renderer("eta").render(ifs, on_window(ifs, 32, {{"norm", "manhattan"}})), InputError);
  EXPECT_THROW(renderer("cma").render(ifs, on_window(ifs, 32, {{"threshold", "-1"}})), InputError);
  RenderOptions prr = on_window(ifs, 32, {{"anything", "1"}});
  EXPECT_THROW(check_parameters(renderer("prr"), prr), InputError);  // PRR takes none
  // Image-plane algorithms refuse 3D systems and say which to use.
  const Ifs pyramid = sample("sierpinski_pyramid");
  try {
    renderer("dia").render(pyramid, on_window(pyramid, 32));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("string-rewriting"), std::string::npos) << e.what();
  }
  EXPECT_GT(renderer("tsa").render(pyramid, on_window(pyramid, 64)).covered(), 100u);
}

TEST(Algorithms, JsonExtensionsReportTheirErrors) {
  auto error_of = [](const std::string& text) {
    try {
      parse_ifs_json(text, "x.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string maps = R"("maps": [{"matrix": [[0.5, 0], [0, 0.5]], "offset": [0, 0]},
                                       {"matrix": [[0.5, 0], [0, 0.5]], "offset": [0.5, 0]}])";
  EXPECT_NE(error_of("{" + maps + R"(, "transitions": [[1, 0], [0, 1]]})").find("/transitions"), std::string::npos);
  EXPECT_NE(error_of("{" + maps + R"(, "transitions": [[1, 1]]})").find("/transitions"), std::string::npos);
  EXPECT_NE(error_of(R"({"maps": [{"matrix": [[0.5, 0], [0, 0.5]], "offset": [0, 0], "probability": 1}],
                         "transitions": [[1]]})").find("/maps/0/probability"), std::string::npos);
  EXPECT_NE(error_of("{" + maps + R"(, "condensation": {"polylines": [[[0, 0]]]}})").find("/condensation"),
            std::string::npos);
  EXPECT_NE(error_of("{" + maps + R"(, "condensation": {"polygons": [], "colour": 1}})").find("/condensation/colour"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"systems": [{"maps": [], "probability": 1}]})").find("/systems/0/maps"), std::string::npos);
  EXPECT_NE(error_of("{" + maps + R"(, "systems": []})").find("/maps"), std::string::npos);
  EXPECT_NE(error_of("{" + maps + R"(, "variability": 3})").find("/variability"), std::string::npos);
}
