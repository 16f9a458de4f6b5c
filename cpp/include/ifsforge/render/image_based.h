#pragma once
/// @file Image-based rendering (seed 5.9, IBR): texture-mapping iteration on the CPU.
#include "ifsforge/render/pixel_space.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// q_0 is the white image; q_k = min(1, sum_i sc_i w_i(q_{k-1})) (Eq. 63), where w_i(q) is the
/// picture q mapped by w_i as a texture: the quadrilateral w_i(image) is rasterised and every
/// pixel in it samples q at its pre-image with bilinear filtering (zero outside the image).
/// Weights: attractor: sc_i = 1, the pixels the copies still ink are the attractor (bilinear
/// filtering lets thin features fade, the seed's "dark image", hence a low threshold); measure:
/// sc_i = p_i / D_i with D_i = |a11 a22 - a12 a21| (Eq. 64), without the clamp, the result is
/// the density of the invariant measure. A map with D_i = 0 (the fern's stem) cannot be
/// sampled backwards: its picture is splatted forwards (pixel centres mapped), carrying the
/// mass p_i in the measure. Iterations (Eq. 65): L = log(max(H, V)) / -log(max_i s_i) + 1,
/// the steps after which the largest copy's diameter falls below a pixel; Eq. 65 as
/// printed, -log(H) / log(max_i D_i), divides by the log of an area ratio, which for
/// similarities (D = s^2) gives half as many. Layouts with colour carry premultiplied channel
/// images transformed by each map's channel rows (the spatial rows must not read them). A
/// condensation set is drawn into every iterate. Raster: density = q where q >= threshold
/// (attractor weights) or the measure density; points = texel samples.
class ImageBased : public Renderer {
 public:
  std::string name() const override { return "ibr"; }
  std::string description() const override {
    return "image-based rendering (5.9): the image texture-mapped by every map, bilinear, Eq. 63-65";
  }
  Capabilities capabilities() const override;
  std::vector<RendererParameter> parameters() const override {
    return {{"weights", "attractor", "attractor (sc_i = 1) or measure (sc_i = p_i / D_i, Eq. 64)"},
            {"iterations", "", "texture passes (default: Eq. 65 for diameters, see the description)"},
            {"threshold", "0.003", "attractor weights: a pixel is covered when q reaches this"},
            supersample_parameter()};
  }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

/// @brief The number of IBR passes after which the largest copy of an image of
/// max(width, height) pixels is smaller than one pixel: log(max(W, H)) / -log(max_i s_i).
int image_based_iterations(const Ifs& ifs, int width, int height);

}  // namespace ifsforge
