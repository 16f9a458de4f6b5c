#include "ifsforge/render/deterministic_iteration.h"

#include <cmath>

#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {
namespace {

/// Largest change of a channel value between two sets with the same pixels, relative to the
/// channel's range.
double channel_change(const PixelSpace& space, const PixelSet& a, const PixelSet& b) {
  double change = 0.0;
  for (std::size_t k = 0; k < a.values.size(); ++k) {
    const int c = static_cast<int>(k % space.channels);
    const double range = space.channel_hi[c] - space.channel_lo[c];
    if (range > 0) change = std::max(change, std::abs(a.values[k] - b.values[k]) / range);
  }
  return change;
}

}  // namespace

Capabilities DeterministicIteration::capabilities() const {
  // The Hutchinson operator on pixel sets: any pieces, C drawn; no transitions.
  using C = Capabilities;
  return {C::Condensation | C::AverageContractive | C::Overlapping | C::Plane};
}

Raster DeterministicIteration::draw(const Ifs& ifs, const RenderOptions& options) const {
  const ParameterValues params(*this, options);
  const int supersample = static_cast<int>(params.integer("supersample", 1, 8));
  const PixelSpace space = make_pixel_space(ifs, options, name(), supersample);
  const long long max_iterations = params.integer("iterations", 1, 1000000);
  const int threads = resolve_threads(options.threads);
  check_memory(space.pixels() * (3.0 * (4.0 + 4.0 * space.channels) + 9.0 + 8.0 * space.channels) +
                   PixelScatter::bytes(space.pixels(), space.channels ? 1 + space.channels : 0, threads),
               "a " + std::to_string(space.width) + "x" + std::to_string(space.height) + " deterministic iteration");
  const Point start = ifs.start_point();
  PixelSet current = full_pixel_set(space, std::vector<float>(start.begin() + 2, start.begin() + 2 + space.channels),
                                    threads, progress_range(options.progress, 0.0, 0.0));
  const PixelSet condensation = condensation_set(ifs, space);
  PixelScatter scatter = set_scatter(space, threads, progress_range(options.progress, 0.0, 0.0));
  std::vector<SetImage> terms;
  for (std::size_t i = 0; i < ifs.size(); ++i) terms.push_back({i, &current});
  std::uint64_t operations = 0;
  for (long long iteration = 0; iteration < max_iterations; ++iteration) {
    // The first passes map every pixel (64 M at 8000^2): progress and Ctrl-C reach inside them.
    const double done = static_cast<double>(iteration) / max_iterations;
    PixelSet next = hutchinson(space, terms, condensation.pixels.empty() ? nullptr : &condensation, scatter,
                               threads, operations, progress_range(options.progress, done, done + 1.0 / max_iterations));
    const bool fixed = next == current && channel_change(space, next, current) < 1e-5;
    current = std::move(next);
    report_progress(options, fixed ? 1.0 : static_cast<double>(iteration + 1) / max_iterations);
    if (fixed) break;
  }
  Raster raster = empty_raster(ifs, space);
  paint_set(current, 1.0f, raster);
  raster.points = operations;
  return reduce_supersampled(std::move(raster), supersample, false);
}

}  // namespace ifsforge
