// The seams between the renderers: one walker for every random-iteration path (model/orbit.h)
// and the systems each renderer, volume renderer and sampler declares it handles
// (model/capabilities.h). A recurrent, a polar, an average-contractive and an overlapping
// system go through every one of them: each is refused with the names of those that handle
// it, or gives the occupied set of the reference (2D chaos) with IoU >= 0.9.
#include <gtest/gtest.h>

#include <chrono>
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/core/random.h"
#include "ifsforge/design/preview.h"
#include "ifsforge/io/ifs_json.h"
#include "ifsforge/model/capabilities.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/render/piece_work.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/volume/volume_renderer.h"
#include "sample_systems.h"

using namespace ifsforge;
using ifsforge::sample_systems::sample;

namespace {

/// Three half-size Sierpinski maps and one that expands by 1.25 about the triangle's middle
/// (p = 0.1): sum p log s = 0.9 log 0.5 + 0.1 log 1.25 < 0 (Eq. 14), so average-contractive.
Ifs average_contractive() {
  const double c[2] = {0.4, 0.3};
  return Ifs("expanding", ChannelLayout("xy"),
             {AffineMap(2, {0.5, 0, 0, 0.5}, {0, 0}), AffineMap(2, {0.5, 0, 0, 0.5}, {0.5, 0}),
              AffineMap(2, {0.5, 0, 0, 0.5}, {0.25, 0.5}),
              AffineMap(2, {1.25, 0, 0, 1.25}, {-0.25 * c[0], -0.25 * c[1]})},
             {0.3, 0.3, 0.3, 0.1});
}

/// Four maps of factor 0.6 into the corners of the unit square: the pieces overlap (sum |det|
/// = 1.44) and the attractor is the filled square.
Ifs overlapping_square() {
  std::vector<AffineMap> maps;
  for (double x : {0.0, 0.4})
    for (double y : {0.0, 0.4}) maps.emplace_back(2, std::vector<double>{0.6, 0, 0, 0.6}, std::vector<double>{x, y});
  return Ifs("overlapping square", ChannelLayout("xy"), maps, {1, 1, 1, 1});
}

std::vector<bool> mask(const Raster& r) {
  std::vector<bool> m(r.density.size());
  for (std::size_t i = 0; i < m.size(); ++i) m[i] = r.density[i] > 0.0f;
  return m;
}

double mask_iou(const std::vector<bool>& a, const std::vector<bool>& b) {
  std::size_t both = 0, either = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    both += a[i] && b[i];
    either += a[i] || b[i];
  }
  return either ? static_cast<double>(both) / either : 1.0;
}

/// A refusal must say why and name exactly the algorithms of its kind that declare they
/// handle the system (none of them the refusing one).
void expect_names_the_alternatives(const std::string& message, const std::string& refusing, const Ifs& ifs,
                                   const std::vector<std::pair<std::string, Capabilities>>& all) {
  const SystemFeatures f = system_features(ifs);
  EXPECT_NE(message.find("'" + refusing + "'"), std::string::npos) << message;
  const std::size_t use = message.rfind("; use ");
  ASSERT_NE(use, std::string::npos) << message;
  const std::string named = message.substr(use);
  for (const auto& [name, caps] : all) {
    const bool handles = unhandled_reason(caps, f, ifs.name()).empty();
    const bool last = named.size() >= name.size() && named.compare(named.size() - name.size(), name.size(), name) == 0;
    const bool listed =
        last || named.find(" " + name + ",") != std::string::npos || named.find(" " + name + " ") != std::string::npos;
    EXPECT_EQ(handles, listed) << name << " in: " << message;
  }
}

struct SystemCase {
  Ifs ifs;
  std::optional<Window> window;
};

std::vector<SystemCase> four_systems() {
  return {{sample("recurrent_squares"), Window{0, 0, 1, 1}},
          {sample("polar_spirals"), std::nullopt},
          {average_contractive(), std::nullopt},
          {overlapping_square(), Window{0, 0, 1, 1}}};
}

}  // namespace

TEST(Walker, AnOrdinaryChainDrawsWhatTheSamplerDraws) {
  const std::vector<double> p = {0.01, 0.85, 0.07, 0.07};
  const MapChain chain(p);
  const MapSampler sampler(p);
  Rng a(7, 3), b(7, 3);
  std::uint32_t state = chain.start(a);  // draws no word for an ordinary system
  EXPECT_FALSE(chain.follows_transitions());
  for (int i = 0; i < 10000; ++i) {
    state = chain.next(state, a.next());
    ASSERT_EQ(state, sampler(b.next()));
  }
}

TEST(Walker, ARecurrentChainNeverTakesAForbiddenStep) {
  const Ifs squares = sample("recurrent_squares");
  const MapChain chain(squares);
  ASSERT_TRUE(chain.follows_transitions());
  Rng rng(1, 0);
  std::uint32_t state = chain.start(rng);
  std::vector<double> seen(4, 0.0);
  constexpr int kSteps = 200000;
  for (int i = 0; i < kSteps; ++i) {
    const std::uint32_t next = chain.next(state, rng.next());
    ASSERT_GT(squares.transitions()(state, next), 0.0) << state << " -> " << next;
    seen[next] += 1.0 / kSteps;
    state = next;
  }
  for (int j = 0; j < 4; ++j) EXPECT_NEAR(seen[j], squares.probabilities()[j], 0.01);  // the stationary law
}

TEST(Capabilities, EveryRandomPathCoversTheRecurrentSquaresLikeChaos) {
  // 4 * 3^4 = 324 of the 1,024 cells of side 1/32 hold an allowed address of length 5.
  const Ifs squares = sample("recurrent_squares");
  RenderOptions o;
  o.width = o.height = 32;
  o.window = Window{0, 0, 1, 1};
  o.binary = true;
  const std::vector<bool> chaos = mask(renderer("chaos").render(squares, o));
  EXPECT_EQ(std::count(chaos.begin(), chaos.end(), true), 324);

  auto picture = std::make_shared<Image>(8, 8, 3);
  for (float& v : picture->pixels) v = 0.5f;
  RenderOptions stolen = o;
  stolen.reference_image = picture;
  EXPECT_EQ(mask(renderer("color-stealing").render(squares, stolen)), chaos);

  auto cell_mask = [&](auto each_point) {
    std::vector<bool> m(32 * 32, false);
    each_point([&](double x, double y) {
      if (x >= 0 && x < 1 && y > 0 && y <= 1) m[std::size_t((1 - y) * 32) * 32 + std::size_t(x * 32)] = true;
    });
    return m;
  };
  EXPECT_EQ(cell_mask([&](auto plot) { sample_attractor(squares, 200000, 5, [&](const Point& p) { plot(p[0], p[1]); }); }),
            chaos);
  // The cloud's float coordinates may round a point onto a cell's edge (long runs of maps
  // that add no binary digit bring points within 2^-24 of one): each point must lie within
  // that of a cell chaos covers, and every such cell must hold a point.
  PreviewOptions preview;
  preview.count = 200000;
  const PreviewCloud cloud = preview_cloud(squares, preview);
  std::vector<bool> hit(32 * 32, false);
  for (std::size_t k = 0; k < cloud.count; ++k) {
    bool near = false;
    for (double dx : {-1e-6, 1e-6})
      for (double dy : {-1e-6, 1e-6}) {
        const double x = cloud.positions[3 * k] + dx, y = cloud.positions[3 * k + 1] + dy;
        if (!(x >= 0 && x < 1 && y > 0 && y <= 1)) continue;
        const std::size_t cell = std::size_t((1 - y) * 32) * 32 + std::size_t(x * 32);
        near = near || chaos[cell];
      }
    ASSERT_TRUE(near) << cloud.positions[3 * k] << " " << cloud.positions[3 * k + 1];
    const double x = cloud.positions[3 * k], y = cloud.positions[3 * k + 1];
    if (x >= 0 && x < 1 && y > 0 && y <= 1) hit[std::size_t((1 - y) * 32) * 32 + std::size_t(x * 32)] = true;
  }
  for (std::size_t cell = 0; cell < hit.size(); ++cell)
    if (chaos[cell]) {
      EXPECT_TRUE(hit[cell]) << cell;
    }
}

TEST(Capabilities, EveryRendererRefusesByNameOrMatchesChaos) {
  auto picture = std::make_shared<Image>(16, 16, 3);
  for (std::size_t i = 0; i < picture->pixels.size(); ++i) picture->pixels[i] = 0.2f + 0.6f * ((i * 7919) % 13) / 13.0f;
  for (const SystemCase& c : four_systems()) {
    RenderOptions o;
    o.width = o.height = 64;
    o.binary = true;
    o.window = c.window ? *c.window : Frame::fit(c.ifs, 64, 64, std::nullopt, View{}).window();
    o.reference_image = picture;
    o.iterations = 4'000'000;  // random iteration: enough points to reach the measure's thin parts
    const std::vector<bool> reference = mask(renderer("chaos").render(c.ifs, o));
    // An expanding map leaves parts of the support so thin that 4M points miss a fifth of
    // its pixels: the set algorithms are held to a long game too (the fast 2D lanes).
    std::vector<bool> converged = reference;
    if (system_features(c.ifs).average_contractive) {
      RenderOptions long_game = o;
      long_game.iterations = 512'000'000;
      converged = mask(renderer("chaos").render(c.ifs, long_game));
    }
    for (const Renderer* r : renderers()) {
      SCOPED_TRACE(r->name() + " on '" + c.ifs.name() + "'");
      const bool declared = unhandled_reason(r->capabilities(), system_features(c.ifs), c.ifs.name()).empty();
      try {
        const Raster raster = r->render(c.ifs, o);
        EXPECT_TRUE(declared);
        EXPECT_GE(std::max(mask_iou(mask(raster), reference), mask_iou(mask(raster), converged)), 0.9);
      } catch (const InputError& e) {
        if (declared) continue;  // a refusal of its own (AFRA: rotation), not a capability
        expect_names_the_alternatives(e.what(), r->name(), c.ifs, renderer_capabilities());
      }
    }
  }
}

TEST(Capabilities, VolumesOfARecurrentSystemFollowTransitionsOrRefuse) {
  // 8 * 7^4 = 19,208 of the 32^3 cells hold an allowed address of length 5.
  const Ifs cubes = sample("recurrent_cubes");
  VolumeOptions o;
  o.resolution = 32;
  o.bounds = Box3{0, 0, 0, 1, 1, 1};
  o.iterations = 4'000'000;
  EXPECT_EQ(volume_renderer("ria").render(cubes, o).size(), 19208u);
  o.iterations = 0;
  for (const VolumeRenderer* r : volume_renderers()) {
    if (r->name() == "ria") continue;
    try {
      r->render(cubes, o);
      ADD_FAILURE() << r->name() << " rendered a recurrent system without its transitions";
    } catch (const InputError& e) {
      expect_names_the_alternatives(e.what(), r->name(), cubes, volume_renderer_capabilities());
    }
  }
}

TEST(Capabilities, SamplersRefuseWhatTheyCannotDraw) {
  const Ifs spirals = sample("polar_spirals");
  try {
    preview_cloud(spirals);
    ADD_FAILURE() << "the preview drew the affine shadows of polar maps";
  } catch (const InputError& e) {
    expect_names_the_alternatives(e.what(), "preview_cloud", spirals, sampler_capabilities());
  }
  EXPECT_NO_THROW(require_sampler_handles("sample_points", spirals));
}

TEST(PieceWork, DeterministicAlgorithmsRefuseAnExpandingMapWithTheReason) {
  const Ifs expanding = average_contractive();
  ASSERT_EQ(expanding.classify(), Classification::AverageContractive);
  RenderOptions o;
  o.width = o.height = 32;
  for (const char* name : {"string-rewriting", "probabilistic-domain", "afra"}) {
    const auto start = std::chrono::steady_clock::now();
    try {
      renderer(name).render(expanding, o);
      ADD_FAILURE() << name << " rendered an average-contractive system";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("average-contractive (map 4 expands space by 1.25 per step)"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("chaos"), std::string::npos) << e.what();
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0) << name;
  }
}

TEST(PieceWork, OverlappingPiecesAreCountedBeforeTheWork) {
  const Ifs square = overlapping_square();
  // Sierpinski: N(x) pieces, D = log 3 / log 2 below the plane's 2; the square's D =
  // log 4 / log(1/0.6) = 2.71 makes the count outgrow the pixels.
  const double at_64 = estimated_pieces(square, 64), at_512 = estimated_pieces(square, 512);
  EXPECT_NEAR(std::log(at_512 / at_64) / std::log(8.0), std::log(4.0) / std::log(1 / 0.6), 0.1);
  RenderOptions o;
  o.width = o.height = 2048;
  o.window = Window{0, 0, 1, 1};
  for (const char* name : {"afra", "string-rewriting", "probabilistic-domain"}) {
    const auto start = std::chrono::steady_clock::now();
    try {
      renderer(name).render(square, o);
      ADD_FAILURE() << name << " split overlapping pieces without a bound";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("they overlap"), std::string::npos) << e.what();
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0) << name;
  }
}
