#include "ifsforge/render/recurrent_photocopy.h"

#include <algorithm>
#include <limits>

#include "ifsforge/model/recurrent.h"
#include "ifsforge/render/mass_transport.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {

Capabilities RecurrentPhotocopy::capabilities() const {
  // One image per map, moved along the transitions.
  using C = Capabilities;
  return {C::Recurrent | C::AverageContractive | C::Overlapping | C::Plane};
}

Raster RecurrentPhotocopy::draw(const Ifs& ifs, const RenderOptions& options) const {
  const ParameterValues params(*this, options);
  const int supersample = static_cast<int>(params.integer("supersample", 1, 8));
  const PixelSpace space = make_pixel_space(ifs, options, name(), supersample);
  const int n = static_cast<int>(ifs.size());
  const int component = params.automatic("component") ? -1 : static_cast<int>(params.integer("component", 0, n - 1));
  const TransitionMatrix transitions = effective_transitions(ifs);
  TransportPlan plan;
  plan.components = n;
  plan.threshold = params.number("threshold", 1e-12, 1.0);
  plan.max_iterations = params.integer("iterations", 1, 1000000);
  plan.spread = spread_mass(params.text("spread"), options.binary);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) plan.weight.push_back(transitions(i, j));
  for (int j = 0; j < n; ++j) plan.target.push_back(j);
  const TransportResult t = transport_mass(ifs, space, plan, options);
  Raster raster = empty_raster(ifs, space);
  for (std::size_t k = 0; k < t.pixel.size(); ++k)
    if (component < 0 || component == t.component[k])
      raster.density[t.pixel[k]] = std::max(raster.density[t.pixel[k]] + static_cast<float>(t.mass[k]),
                                            std::numeric_limits<float>::denorm_min());
  raster.channels.assign(t.channels.begin(), t.channels.end());
  raster.points = t.operations;
  return reduce_supersampled(std::move(raster), supersample, true);
}

}  // namespace ifsforge
