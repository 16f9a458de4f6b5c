#pragma once
/// @file The escape-time algorithm (seed 5.5, ETA) on the shift dynamical system f_i = w_i^-1.
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// Each pixel is iterated under the shift dynamical system (Eq. 54): its square Q is carried
/// by the inverse maps f_j = w_j^-1, since Q meets the piece w_j(A) exactly when f_j(Q) meets A.
/// An image that leaves H, a polygon holding the attractor (12 slabs 15 degrees apart around a
/// seeded sample, widened 2%), has escaped (the seed's max_distance test, exact for
/// parallelograms); an image that holds a known point of the attractor (a fixed point, or one of
/// 64 sample points once the image is large) or swallows H proves that the pixel holds a point
/// of the attractor. Where the pieces overlap, several f_j keep Q inside B: they are tried in the
/// order of the delta norm of Eq. 55 (Euclidean |f_j(c) - c| or linear |dx| + |dy| at Q's
/// centre c), smallest first (rule min) or largest first (rule max), Eq. 56. The order decides
/// how soon a covered pixel is proved, never whether it is: the image does not depend on the
/// norm or the rule, only the work does. The escape time of a pixel is the deepest level any
/// of its images reached before all escaped. A map with no inverse (|det| = 0, e.g. the fern's
/// stem) cannot be iterated back: a pixel whose image meets w_j of H's bounding box counts as
/// covered.
/// Every pixel is computed on its own, so any window (a zoom) renders exactly the pixels a
/// larger image would have there. Raster: output attractor: density 1 on covered pixels;
/// output escape-time: density = escape time + 1 on every pixel (covered pixels iterations + 1);
/// channels: the point of the attractor found in the pixel; points = inverse-map applications.
class EscapeTime : public Renderer {
 public:
  std::string name() const override { return "eta"; }
  std::string description() const override {
    return "escape time (5.5): pixels iterated by the inverse maps until they leave the attractor's box";
  }
  Capabilities capabilities() const override;
  std::vector<RendererParameter> parameters() const override {
    return {{"norm", "euclidean", "delta norm of Eq. 55: euclidean or linear"},
            {"rule", "min", "Eq. 56: try the map with the min or the max delta first"},
            {"iterations", "100", "max_no_of_iterations: deepest level (a pixel still undecided there counts as covered)"},
            {"output", "attractor", "attractor (covered pixels) or escape-time (the escape time of every pixel)"}};
  }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

}  // namespace ifsforge
