#pragma once
/// @file `render -a tops`: the attractor coloured by its top addresses (seed 3.3.5, Fig. 3.14).
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// Each pixel q of the attractor takes the reference picture's colour at phi_R(tau_F(q)): the
/// point with q's top address on the reference system R (default: the grid of
/// grid_reference_system over the unit square, laid on the picture). Unlike colour stealing
/// (5.1.2), which averages the colours of every point in a pixel, one address decides.
class TopsRenderer : public Renderer {
 public:
  std::string name() const override { return "tops"; }
  std::string description() const override {
    return "fractal tops (3.3.5): colors of a reference image at the top address of each pixel";
  }
  Capabilities capabilities() const override;

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

}  // namespace ifsforge
