#pragma once
/// @file Colour-stealing random iteration (seed 5.1.2).
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// Two systems with the same number of maps iterate with one random sequence: the target
/// system draws the attractor, the reference system walks a reference picture (its unit
/// square, or the default system's rectangle, stretched over the picture), and each plotted point takes the picture's colour
/// (bilinear) under the reference point. Pixels show the mean stolen colour.
class ColorStealing : public Renderer {
 public:
  std::string name() const override { return "color-stealing"; }
  std::string description() const override {
    return "color-stealing random iteration (5.1.2): colors taken from a reference image";
  }
  Capabilities capabilities() const override;

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

/// @brief The default reference system, contractive for any map count: its attractor is the
/// rectangle [0, 1] x [0, 1/sqrt N] (stretched over the picture) and map i sends it, turned a
/// quarter, onto the i-th of N vertical strips (a similarity with factor 1/sqrt N).
Ifs grid_reference_system(std::size_t maps);
/// @brief The height of grid_reference_system(maps)'s rectangle (its width is 1).
double grid_reference_height(std::size_t maps);

}  // namespace ifsforge
