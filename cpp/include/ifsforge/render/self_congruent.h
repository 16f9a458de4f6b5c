#pragma once
/// @file Rendering of self-congruent IFS (seed 5.11): a structure grown cycle by cycle.
#include <vector>

#include "ifsforge/render/pixel_space.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// Two processors, as in the seed's Fig. 5.14: the first supplies the initiator (the system's
/// condensation set, e.g. a trunk; without one, the pixels of the maps' fixed points), the
/// second transforms shapes with the IFS maps. Generation 0 is the initiator; generation g is
/// the image under the maps of generation g - 1, less what had grown already (on the pixel
/// grid, centres mapped and rounded as in 5.2-5.3). A growth cycle adds `cycle` generations,
/// and frame k shows everything grown in the first k cycles: the structure grows until no new
/// pixel appears (the attractor with its condensation set, C u W(C) u W^2(C) u ...).
/// Raster: frame `frame` (default: the last one), density = the age of each pixel in cycles
/// (1 = grown in the frame shown), channels = the values it was grown with; points = map
/// applications.
class SelfCongruent : public Renderer {
 public:
  std::string name() const override { return "self-congruent"; }
  std::string description() const override {
    return "self-congruent growth (5.11): the initiator transformed cycle by cycle; frame k after k cycles";
  }
  Capabilities capabilities() const override;
  std::vector<RendererParameter> parameters() const override {
    return {{"frame", "", "the frame to show (cycles grown; default: the last, when growth stops)"},
            {"cycle", "1", "generations of growth per cycle (frame)"},
            {"generations", "100000", "stop growing after this many generations"},
            supersample_parameter()};
  }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

/// @brief Every frame of the growth, frame 0 (the initiator) to the last (same parameters as
/// the renderer except `frame`).
std::vector<Raster> growth_frames(const Ifs& ifs, const RenderOptions& options);

}  // namespace ifsforge
