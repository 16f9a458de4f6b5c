#include <cmath>
#include <memory>

#include "ifsforge/core/error.h"
#include "ifsforge/core/named.h"
#include "ifsforge/render/accurate_fractal.h"
#include "ifsforge/render/chaos_game.h"
#include "ifsforge/render/color_stealing.h"
#include "ifsforge/render/tops_renderer.h"
#include "ifsforge/render/constant_mass.h"
#include "ifsforge/render/deterministic_iteration.h"
#include "ifsforge/render/escape_time.h"
#include "ifsforge/render/image_based.h"
#include "ifsforge/render/minimal_plotting.h"
#include "ifsforge/render/point_recursive.h"
#include "ifsforge/render/probabilistic_domain.h"
#include "ifsforge/render/recurrent_photocopy.h"
#include "ifsforge/render/self_congruent.h"
#include "ifsforge/render/string_rewriting.h"
#include "ifsforge/render/superfractal.h"
#include "ifsforge/render/tesseral_synecdoche.h"

namespace ifsforge {
namespace {

struct Entry {
  std::unique_ptr<Renderer> renderer;
  std::vector<std::string> aliases;
  SeedReference seed;  ///< where the seed describes it, and its 5.13.1 operation estimate
};

const std::vector<Entry>& registry() {
  static const std::vector<Entry> entries = [] {
    // The seed's section of each algorithm and its operation estimate for H = V = 1000, N = 5
    // (5.13.1, Eq. 75-88; 0: the seed gives none).
    std::vector<Entry> e;
    e.push_back({std::make_unique<ChaosGame>(), {"ria", "random"}, {"5.1.1", 8e6}});
    e.push_back({std::make_unique<ColorStealing>(), {"cs-ria", "color-stealing"}, {"5.1.2", 8e6}});
    e.push_back({std::make_unique<DeterministicIteration>(), {"deterministic-iteration"}, {"5.2.1", 100e6}});
    e.push_back({std::make_unique<Superfractal>(), {"superfractal"}, {"5.2.2", 320e6}});
    e.push_back({std::make_unique<MinimalPlotting>(), {"minimal-plotting"}, {"5.3", 0.5e6}});
    e.push_back({std::make_unique<ConstantMass>(), {"constant-mass"}, {"5.4", 100e6}});
    e.push_back({std::make_unique<EscapeTime>(), {"escape-time"}, {"5.5", 1.28e9}});
    e.push_back({std::make_unique<StringRewriting>(), {}, {"5.6", 781250}});
    e.push_back({std::make_unique<TesseralSynecdoche>(), {}, {"5.7", 0.8e6}});
    e.push_back({std::make_unique<PointRecursive>(), {"point-recursive"}, {"5.8.1", 390625}});
    e.push_back({std::make_unique<ImageBased>(), {"image-based"}, {"5.9", 1e6}});
    e.push_back({std::make_unique<AccurateFractal>(), {"accurate-fractal"}, {"5.10", 780000}});
    e.push_back({std::make_unique<SelfCongruent>(), {"growth"}, {"5.11", 0}});
    e.push_back({std::make_unique<RecurrentPhotocopy>(), {"recurrent-photocopy"}, {"5.12.1", 0}});
    e.push_back({std::make_unique<ProbabilisticDomain>(), {"vrpda"}, {"5.12.2", 0}});
    e.push_back({std::make_unique<TopsRenderer>(), {"fractal-tops"}, {"3.3.5", 0}});  // after chapter 5
    return e;
  }();
  return entries;
}

}  // namespace

std::string Renderer::draw_jobs(const Ifs&, const RenderOptions&, std::uint64_t, std::uint64_t) const {
  throw InputError("the " + name() + " renderer does not split into independent jobs: distribute chaos or prr");
}

const std::vector<std::pair<std::string, Capabilities>>& renderer_capabilities() {
  static const std::vector<std::pair<std::string, Capabilities>> all = capability_table(registry());
  return all;
}

void Renderer::require_handles(const Ifs& ifs) const {
  ifsforge::require_handles("algorithm", name(), capabilities(), ifs, renderer_capabilities());
}

Raster Renderer::render(const Ifs& ifs, const RenderOptions& options) const {
  require_handles(ifs);
  return draw(ifs, options);
}

std::string Renderer::run_jobs(const Ifs& ifs, const RenderOptions& options, std::uint64_t first,
                               std::uint64_t last) const {
  require_handles(ifs);
  return draw_jobs(ifs, options, first, last);
}

const Renderer& renderer(const std::string& name) { return find_named(registry(), name, "algorithm"); }

SeedReference seed_reference(const std::string& name) {
  const Renderer* r = &renderer(name);
  for (const auto& entry : registry())
    if (entry.renderer.get() == r) return entry.seed;
  return {};
}

std::vector<const Renderer*> renderers() {
  std::vector<const Renderer*> out;
  for (const auto& entry : registry()) out.push_back(entry.renderer.get());
  return out;
}

std::uint64_t default_iterations(int width, int height, bool binary, double points_per_pixel) {
  const double pixels = static_cast<double>(width) * height;
  if (binary) return static_cast<std::uint64_t>(pixels * std::log(1.78107 * pixels));  // Eq. 45
  return static_cast<std::uint64_t>(pixels * 8.0 * points_per_pixel);                  // Eq. 44
}

int default_depth(std::size_t maps, int width, int height) {
  if (maps < 2) return 1;
  const double pixels = static_cast<double>(width) * height;
  return static_cast<int>(std::ceil(std::log(pixels) / std::log(static_cast<double>(maps))));  // Eq. 59
}

}  // namespace ifsforge
