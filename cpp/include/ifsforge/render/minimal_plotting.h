#pragma once
/// @file Minimal plotting (seed 5.3, MPA): a queue of pixels, each plotted and mapped once.
#include "ifsforge/render/pixel_space.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// The pixels of the maps' fixed points (and of the condensation set) are plotted and queued;
/// each pixel taken from the queue has its centre mapped by every map, rounded to the pixel
/// holding it, and every pixel not yet plotted is plotted and queued. A pixel enters the queue
/// at most once, so the work is N map applications per plotted pixel. By the proximity
/// theorem (Theorem 5, Eq. 53) every plotted pixel lies within proximity_bound() of the
/// attractor; the theorem needs a hyperbolic system. Pixels keep the channel values of the
/// point that plotted them. Raster: density = the number of times the pixel was taken from the
/// queue (1 on every plotted pixel; with supersample k, the most any of its cells was taken);
/// points = map applications.
class MinimalPlotting : public Renderer {
 public:
  std::string name() const override { return "mpa"; }
  std::string description() const override {
    return "minimal plotting (5.3): a queue of pixels, each mapped once; within delta/(1-s) of the attractor (Eq. 53)";
  }
  Capabilities capabilities() const override;
  std::vector<RendererParameter> parameters() const override { return {supersample_parameter()}; }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

/// @brief Eq. 53: delta / (1 - s), delta half the pixel diagonal of `frame` and s the largest
/// spatial contraction factor; the distance from any pixel the MPA plots to the attractor is at
/// most this. InputError unless the system is hyperbolic in space.
double proximity_bound(const Ifs& ifs, const class Frame& frame);

}  // namespace ifsforge
