#pragma once
/// @file The vector recurrent grayscale photo-copy algorithm (seed 5.12.1).
#include "ifsforge/render/mass_transport.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// A recurrent IFS encodes N images I_j, one per map: the pieces A_j of its attractor, each
/// with its share of the measure. The vector Markov operator (Eq. 71-72) takes the images to
/// (M I)_j = sum_i P(i, j) w_j(I_i): the mass of image i at every pixel goes, in the share
/// P(i, j), to the pixel holding w_j of that pixel in image j. Starting from uniform images it
/// is iterated like the constant mass algorithm until the L1 change is below `threshold` and
/// the images' supports stop changing. An ordinary IFS takes P(i, j) = p_j. Raster: density =
/// the measure of component `component` (default: all superimposed); points = map
/// applications.
class RecurrentPhotocopy : public Renderer {
 public:
  std::string name() const override { return "photocopy"; }
  std::string description() const override {
    return "vector recurrent photo-copy (5.12.1): the vector Markov operator on one image per map";
  }
  Capabilities capabilities() const override;
  std::vector<RendererParameter> parameters() const override {
    return {{"component", "", "show only image I_j of map j (0-based); default: every component superimposed"},
            {"threshold", "0.001", "stop when the L1 change of the normalized images falls below this"},
            {"iterations", "1000", "most iterations"},
            spread_parameter(),
            supersample_parameter()};
  }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

}  // namespace ifsforge
