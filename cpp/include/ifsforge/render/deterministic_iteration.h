#pragma once
/// @file Deterministic iteration (seed 5.2.1): the Hutchinson operator on a pixel buffer.
#include "ifsforge/render/pixel_space.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// Starts from the whole image (the seed's uniformly grey picture) and replaces it by the
/// union of its images under the maps, each pixel's centre mapped and rounded to the pixel
/// holding it (two buffers, Eq. 50 without the weights). From a set that holds the attractor
/// the iterates shrink monotonically, so the loop stops at the first iterate equal to the one
/// before (a fixed point of the discrete operator), or after `iterations`. A condensation set
/// is added to every iterate (W(B) = C u w_1(B) u ..., Eq. 15). Pixels carry the mean of the
/// channel values mapped into them. Raster: density 1 on the set; points = map applications.
class DeterministicIteration : public Renderer {
 public:
  std::string name() const override { return "dia"; }
  std::string description() const override {
    return "deterministic iteration (5.2.1): the Hutchinson operator on a pixel buffer until it stops changing";
  }
  Capabilities capabilities() const override;
  std::vector<RendererParameter> parameters() const override {
    return {{"iterations", "100", "most buffer rewrites (the loop ends earlier at a fixed point; Barnsley suggests 100)"},
            supersample_parameter()};
  }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

}  // namespace ifsforge
