#include "ifsforge/render/superfractal.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/map_sampler.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {

Capabilities Superfractal::capabilities() const {
  // Deterministic iteration on V buffers: as dia.
  using C = Capabilities;
  return {C::Condensation | C::AverageContractive | C::Overlapping | C::Plane};
}

Raster Superfractal::draw(const Ifs& ifs, const RenderOptions& options) const {
  const ParameterValues params(*this, options);
  const int supersample = static_cast<int>(params.integer("supersample", 1, 8));
  const PixelSpace space = make_pixel_space(ifs, options, name(), supersample);
  const SuperIfs& parts = ifs.super_ifs();
  const int variability = params.automatic("variability") ? (parts.empty() ? 2 : parts.variability)
                                                          : static_cast<int>(params.integer("variability", 1, 64));
  const int buffer = static_cast<int>(params.integer("buffer", 0, variability - 1));
  long long iterations = 0;
  if (params.automatic("iterations")) {
    // Enough rewrites for the largest copy of the image to shrink below half a pixel: the
    // buffers then no longer remember the start at pixel size (the seed's ~20 for its screens).
    double s = 0.0;
    for (double f : ifs.spatial_contraction_factors()) s = std::max(s, f);
    const double diagonal = std::hypot(space.width, space.height);  // cells of the (finer) grid
    iterations = s > 0.0 && s < 1.0 ? static_cast<long long>(std::ceil(std::log(0.5 / diagonal) / std::log(s))) + 2 : 20;
  } else {
    iterations = params.integer("iterations", 1, 100000);
  }
  const int threads = resolve_threads(options.threads);
  check_memory(space.pixels() * (2.0 * variability + 1.0) * (4.0 + 4.0 * space.channels) +
                   PixelScatter::bytes(space.pixels(), space.channels ? 1 + space.channels : 0, threads),
               std::to_string(variability) + " superfractal buffers of " + std::to_string(space.width) + "x" +
                   std::to_string(space.height));

  // Members: [first map, size] and their probabilities; an ordinary IFS is one member.
  std::vector<std::size_t> first, size;
  std::vector<double> member_p;
  if (parts.empty()) {
    first = {0};
    size = {ifs.size()};
    member_p = {1.0};
  } else {
    for (std::size_t n = 0; n < parts.members(); ++n) {
      first.push_back(parts.first_map(n));
      size.push_back(parts.sizes[n]);
    }
    member_p = parts.probabilities;
  }
  const MapSampler pick_member(member_p);
  Rng rng(options.seed, 0);

  const Point start = ifs.start_point();
  const std::vector<float> start_values(start.begin() + 2, start.begin() + 2 + space.channels);
  // Every buffer starts as the same full image: shared, not copied (a copy per buffer cost
  // seconds of first touch at 16000^2 before the first progress check).
  const PixelSet full = full_pixel_set(space, start_values, threads, progress_range(options.progress, 0.0, 0.0));
  std::vector<PixelSet> buffers(variability);
  std::vector<const PixelSet*> current(variability, &full);
  const PixelSet condensation = condensation_set(ifs, space);
  PixelScatter scatter = set_scatter(space, threads, progress_range(options.progress, 0.0, 0.0));
  std::uint64_t operations = 0;
  for (long long iteration = 0; iteration < iterations; ++iteration) {
    std::vector<PixelSet> next(variability);
    for (int v = 0; v < variability; ++v) {
      const std::uint32_t n = pick_member(rng.next());
      std::vector<SetImage> terms;
      for (std::size_t m = 0; m < size[n]; ++m)
        terms.push_back({first[n] + m, current[rng.next() % static_cast<std::uint64_t>(variability)]});
      const double done = (iteration + static_cast<double>(v) / variability) / iterations;
      next[v] = hutchinson(space, terms, condensation.pixels.empty() ? nullptr : &condensation, scatter, threads,
                           operations, progress_range(options.progress, done, done + 1.0 / (variability * iterations)));
    }
    buffers.swap(next);
    for (int v = 0; v < variability; ++v) current[v] = &buffers[v];
    report_progress(options, static_cast<double>(iteration + 1) / iterations);
  }
  Raster raster = empty_raster(ifs, space);
  paint_set(*current[buffer], 1.0f, raster);
  raster.points = operations;
  return reduce_supersampled(std::move(raster), supersample, false);
}

}  // namespace ifsforge
