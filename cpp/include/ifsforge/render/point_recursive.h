#pragma once
/// @file Point recursive rendering (seed 5.8.1).
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// PRR(q, L): for every map i, q1 = w_i(q); plot q1 at the leaves, else recurse. The leaf
/// mass is the product of the probabilities along the address, so the raster holds the
/// invariant measure. With options.depth > 0 every leaf sits at exactly that depth, as in
/// the seed. With depth 0 a branch also stops as soon as its whole sub-attractor fits in
/// half a pixel (product of contraction factors times the attractor's radius), which puts
/// every pixel within one pixel of the attractor at far fewer leaves than Eq. 59's N^L.
/// Jobs are address prefixes, merged in address order: the seam a distributed scheduler can
/// cut along, and the reason the output does not depend on the thread count.
class PointRecursive : public Renderer {
 public:
  std::string name() const override { return "prr"; }
  std::string description() const override {
    return "point recursive rendering (5.8.1): deterministic, measure per pixel";
  }
  Raster render(const Ifs& ifs, const RenderOptions& options) const override;
};

}  // namespace ifsforge
