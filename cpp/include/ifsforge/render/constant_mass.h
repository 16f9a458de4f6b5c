#pragma once
/// @file The constant mass algorithm (seed 5.4, CMA): the measure by redistributing mass.
#include "ifsforge/render/mass_transport.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// Every pixel starts with the same mass (the seed's uniform grey value). Each iteration moves
/// the mass of every pixel q, a share p_j to each map, to where w_j takes it (the seed's
/// target(w_j(q)) += p_j mass(q), the Markov operator of Eq. 50). Each pixel remembers the
/// centroid of its mass (an affine map sends the centroid of the mass to the centroid of its
/// image); with `spread` box the mass is shared among the cells its image overlaps, which keeps
/// the measure within a few percent (L1) of random iteration's, while the seed's rounding to
/// one cell (spread none, the default for binary images) keeps thin curves thin. The total stays 1 (mass that
/// leaves the window is dropped and the rest rescaled). The loop ends when the L1 change of
/// the mass is below `threshold` and the set of pixels holding mass no longer changes. A
/// condensation set receives a share p_0 of the mass, spread evenly over its pixels, at every
/// step. Raster: density = the mass of each pixel (the invariant measure, like chaos and prr),
/// channels = mass-weighted means; points = map applications.
class ConstantMass : public Renderer {
 public:
  std::string name() const override { return "cma"; }
  std::string description() const override {
    return "constant mass (5.4): mass moved by the maps with their probabilities until it settles (the measure)";
  }
  Capabilities capabilities() const override;
  std::vector<RendererParameter> parameters() const override {
    return {{"threshold", "0.001", "stop when the L1 change of the normalized mass falls below this"},
            {"iterations", "1000", "most iterations"},
            spread_parameter(),
            supersample_parameter()};
  }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

}  // namespace ifsforge
