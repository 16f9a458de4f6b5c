#include "ifsforge/render/self_congruent.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {
namespace {

struct Growth {
  PixelSpace space;
  std::vector<std::int32_t> birth;  ///< generation each pixel grew in, -1 never
  std::vector<float> values;        ///< pixels x channels: the values it grew with
  int generations = 0;              ///< last generation that added pixels
  int cycle = 1;
  int supersample = 1;
  std::uint64_t operations = 0;
};

Growth grow(const Ifs& ifs, const RenderOptions& options, const ParameterValues& params, const std::string& name) {
  Growth g;
  g.supersample = static_cast<int>(params.integer("supersample", 1, 8));
  g.space = make_pixel_space(ifs, options, name, g.supersample);
  const PixelSpace& space = g.space;
  g.cycle = static_cast<int>(params.integer("cycle", 1, 1000000));
  const long long limit = params.integer("generations", 1, 10000000);
  const int threads = resolve_threads(options.threads);
  const int channels = space.channels;
  check_memory(space.pixels() * (4.0 + 12.0 * (1 + channels)) +
                   PixelScatter::bytes(space.pixels(), channels ? 1 + channels : 0, threads),
               "a " + std::to_string(space.width) + "x" + std::to_string(space.height) + " growth");
  g.birth.assign(space.pixels(), -1);
  g.values.assign(space.pixels() * channels, 0.0f);

  // Processor 1: the initiator.
  PixelSet fresh = condensation_set(ifs, space);
  if (fresh.pixels.empty()) {
    std::vector<std::pair<std::uint32_t, std::vector<float>>> seeds;
    for (const Point& p : ifs.fixed_points()) {
      if (!std::isfinite(p[0]) || !std::isfinite(p[1])) continue;
      const auto px = space.frame.to_pixel(p);
      const long long pixel = space.pixel_at(px[0], px[1]);
      if (pixel >= 0) seeds.push_back({static_cast<std::uint32_t>(pixel), std::vector<float>(p.begin() + 2, p.begin() + 2 + channels)});
    }
    std::stable_sort(seeds.begin(), seeds.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (std::size_t k = 0; k < seeds.size(); ++k) {
      if (k > 0 && seeds[k].first == seeds[k - 1].first) continue;
      fresh.pixels.push_back(seeds[k].first);
      fresh.values.insert(fresh.values.end(), seeds[k].second.begin(), seeds[k].second.end());
    }
  }
  PixelScatter scatter = set_scatter(space, threads, progress_range(options.progress, 0.0, 0.0));
  // Processor 2: the maps, applied to what grew last.
  for (int generation = 0; !fresh.pixels.empty(); ++generation) {
    for (std::size_t k = 0; k < fresh.pixels.size(); ++k) {
      g.birth[fresh.pixels[k]] = generation;
      std::copy(fresh.values.begin() + k * channels, fresh.values.begin() + (k + 1) * channels,
                g.values.begin() + std::size_t(fresh.pixels[k]) * channels);
    }
    g.generations = generation;
    if (generation + 1 > limit) break;
    std::vector<SetImage> terms;
    for (std::size_t i = 0; i < ifs.size(); ++i) terms.push_back({i, &fresh});
    const PixelSet images = hutchinson(space, terms, nullptr, scatter, threads, g.operations);
    PixelSet next;
    for (std::size_t k = 0; k < images.pixels.size(); ++k) {
      if (g.birth[images.pixels[k]] >= 0) continue;
      next.pixels.push_back(images.pixels[k]);
      next.values.insert(next.values.end(), images.values.begin() + k * channels, images.values.begin() + (k + 1) * channels);
    }
    fresh = std::move(next);
    report_progress(options, 1.0 - 1.0 / (2.0 + generation));
  }
  return g;
}

int last_frame(const Growth& g) { return (g.generations + g.cycle - 1) / g.cycle; }

Raster frame_raster(const Ifs& ifs, const Growth& g, int frame) {
  Raster raster = empty_raster(ifs, g.space);
  const int channels = g.space.channels;
  const long long grown = static_cast<long long>(frame) * g.cycle;
  for (std::size_t p = 0; p < g.birth.size(); ++p) {
    if (g.birth[p] < 0 || g.birth[p] > grown) continue;
    const int born_in = (g.birth[p] + g.cycle - 1) / g.cycle;  // the cycle that grew it
    raster.density[p] = static_cast<float>(frame - born_in + 1);
    for (int c = 0; c < channels; ++c) raster.channels[p * channels + c] = g.values[p * channels + c];
  }
  raster.points = g.operations;
  return reduce_supersampled(std::move(raster), g.supersample, false);
}

}  // namespace

Capabilities SelfCongruent::capabilities() const {
  // Growth from the initiator on pixel sets.
  using C = Capabilities;
  return {C::Condensation | C::AverageContractive | C::Overlapping | C::Plane};
}

Raster SelfCongruent::draw(const Ifs& ifs, const RenderOptions& options) const {
  const ParameterValues params(*this, options);
  const Growth g = grow(ifs, options, params, name());
  const int last = last_frame(g);
  const int frame = params.automatic("frame") ? last : static_cast<int>(params.integer("frame", 0, 100000000));
  return frame_raster(ifs, g, std::min(frame, last));
}

std::vector<Raster> growth_frames(const Ifs& ifs, const RenderOptions& options) {
  const SelfCongruent renderer;
  renderer.require_handles(ifs);  // the frames come from grow(), not through render()
  const ParameterValues params(renderer, options);
  const Growth g = grow(ifs, options, params, renderer.name());
  const int last = last_frame(g);
  check_memory((last + 1.0) * g.space.pixels() * 4.0 * (1 + g.space.channels),
               std::to_string(last + 1) + " growth frames");
  std::vector<Raster> frames;
  for (int k = 0; k <= last; ++k) frames.push_back(frame_raster(ifs, g, k));
  return frames;
}

}  // namespace ifsforge
