#pragma once
/// @file Point recursive rendering (seed 5.8.1).
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// PRR(q, L): for every map i, q1 = w_i(q); plot q1 at the leaves, else recurse. Each leaf
/// plots w_a1 o ... o w_aL (q0) for the fixed point q0, with the product of the probabilities
/// along the address as its mass, so the raster holds the invariant measure.
/// With options.depth > 0 every leaf sits at exactly that depth, as in the seed (N^L leaves).
/// With depth 0 a branch stops as soon as its piece of the attractor (inside the box M(B) of
/// recursion.h) provably lies inside one pixel, which then receives exactly the piece's measure,
/// or is smaller than a pixel; such a straddling piece plots the images of a few attractor
/// points spread over it (W^d of the fixed points) so that no pixel it touches is missed.
/// This needs far fewer leaves than Eq. 59's N^L. Branches that miss the image are pruned in
/// both modes. Jobs are address prefixes merged in address order. Systems with polar maps
/// (3.3.3) estimate the size of a piece from the images of a few attractor points instead
/// (Eq. 30 bounds distances from a centre, not diameters: see polar_recursive.cpp).
class PointRecursive : public Renderer {
 public:
  std::string name() const override { return "prr"; }
  std::string description() const override {
    return "point recursive rendering (5.8.1): deterministic, measure per pixel";
  }
  Capabilities capabilities() const override;
  bool distributable() const override { return true; }
  std::vector<RendererParameter> parameters() const override {
    return {{"cut", "",
             "pixels: a piece smaller than this that straddles pixel edges is not split further but "
             "spread over its sub-pieces; automatic: 1 for the measure (1/8 brings it within about 0.02 "
             "in L1 of a long chaos game, for several times the work), 1/2 for coverage (binary)"}};
  }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
  /// Jobs' leaves in address order (render() applies them in that order: exact float sums).
  std::string draw_jobs(const Ifs& ifs, const RenderOptions& options, std::uint64_t first,
                        std::uint64_t last) const override;
};

}  // namespace ifsforge
