#include "ifsforge/render/minimal_plotting.h"

#include <algorithm>
#include <cmath>
#include <deque>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {

double proximity_bound(const Ifs& ifs, const Frame& frame) {
  double s = 0.0;
  for (double f : ifs.spatial_contraction_factors()) s = std::max(s, f);
  if (!(s < 1.0))
    throw InputError("minimal plotting needs a hyperbolic system (Theorem 5): system '" + ifs.name() +
                     "' has a map with contraction factor " + std::to_string(s));
  const double delta = 0.5 * std::sqrt(2.0) * frame.pixel_size();
  return delta / (1.0 - s);
}

Capabilities MinimalPlotting::capabilities() const {
  // Theorem 5 needs every map to contract.
  using C = Capabilities;
  return {C::Condensation | C::Overlapping | C::Plane};
}

Raster MinimalPlotting::draw(const Ifs& ifs, const RenderOptions& options) const {
  const ParameterValues params(*this, options);
  const int supersample = static_cast<int>(params.integer("supersample", 1, 8));
  const PixelSpace space = make_pixel_space(ifs, options, name(), supersample);
  proximity_bound(ifs, space.frame);  // refuses non-hyperbolic systems
  const int channels = space.channels;
  check_memory(space.pixels() * (2.0 + 4.0 + 4.0 * channels) + space.pixels() * (4.0 + 4.0 * channels),
               "a " + std::to_string(space.width) + "x" + std::to_string(space.height) + " minimal plotting");
  Raster raster = empty_raster(ifs, space);
  std::deque<std::uint32_t> queue;
  std::vector<float> values(space.pixels() * channels, 0.0f);  // channel values of plotted pixels
  std::vector<std::uint8_t> plotted(space.pixels(), 0);
  auto plot = [&](long long pixel, const double* channel_values) {
    if (pixel < 0 || plotted[pixel]) return;
    plotted[pixel] = 1;
    for (int c = 0; c < channels; ++c) values[pixel * channels + c] = static_cast<float>(channel_values[c]);
    queue.push_back(static_cast<std::uint32_t>(pixel));
  };
  // Seeds: the fixed points of the maps (they lie on the attractor), then the condensation set.
  for (const Point& p : ifs.fixed_points()) {
    if (!std::isfinite(p[0]) || !std::isfinite(p[1])) continue;
    const auto px = space.frame.to_pixel(p);
    plot(space.pixel_at(px[0], px[1]), p.data() + 2);
  }
  const PixelSet condensation = condensation_set(ifs, space);
  for (std::size_t k = 0; k < condensation.pixels.size(); ++k) {
    double v[kMaxDim];
    for (int c = 0; c < channels; ++c) v[c] = condensation.values[k * channels + c];
    plot(condensation.pixels[k], v);
  }
  std::uint64_t operations = 0, taken = 0;
  double mapped[kMaxDim];
  while (!queue.empty()) {
    const std::uint32_t q = queue.front();
    queue.pop_front();
    raster.density[q] += 1.0f;  // how often this pixel was taken from the queue
    // data(), not &values[...]: values is empty without channels.
    for (std::size_t i = 0; i < space.maps.size(); ++i) plot(space.map_pixel(i, q, values.data() + std::size_t(q) * channels, mapped), mapped);
    operations += space.maps.size();
    if ((++taken & 0xFFFFF) == 0) report_progress(options, 1.0 - 1.0 / (1.0 + taken / 1e6));
  }
  for (std::size_t p = 0; p < space.pixels(); ++p)
    for (int c = 0; c < channels && raster.density[p] > 0.0f; ++c) raster.channels[p * channels + c] = values[p * channels + c];
  raster.points = operations;
  report_progress(options, 1.0);
  return reduce_supersampled(std::move(raster), supersample, false);
}

}  // namespace ifsforge
