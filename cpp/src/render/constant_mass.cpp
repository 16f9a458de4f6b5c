#include "ifsforge/render/constant_mass.h"

#include <algorithm>
#include <limits>

#include "ifsforge/render/mass_transport.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {

Capabilities ConstantMass::capabilities() const {
  // The Markov operator on pixels: the measure of any system that has one.
  using C = Capabilities;
  return {C::Condensation | C::AverageContractive | C::Overlapping | C::Plane};
}

Raster ConstantMass::draw(const Ifs& ifs, const RenderOptions& options) const {
  const ParameterValues params(*this, options);
  const int supersample = static_cast<int>(params.integer("supersample", 1, 8));
  const PixelSpace space = make_pixel_space(ifs, options, name(), supersample);
  TransportPlan plan;
  plan.threshold = params.number("threshold", 1e-12, 1.0);
  plan.max_iterations = params.integer("iterations", 1, 1000000);
  plan.spread = spread_mass(params.text("spread"), options.binary);
  const double share = ifs.condensation().empty() ? 0.0 : ifs.condensation().probability;
  plan.condensation_share = share;
  for (double p : ifs.probabilities()) plan.weight.push_back(p * (1.0 - share));
  plan.target.assign(ifs.size(), 0);
  const TransportResult t = transport_mass(ifs, space, plan, options);
  Raster raster = empty_raster(ifs, space);
  for (std::size_t k = 0; k < t.pixel.size(); ++k)
    raster.density[t.pixel[k]] = std::max(static_cast<float>(t.mass[k]), std::numeric_limits<float>::denorm_min());
  raster.channels.assign(t.channels.begin(), t.channels.end());
  raster.points = t.operations;
  return reduce_supersampled(std::move(raster), supersample, true);
}

}  // namespace ifsforge
