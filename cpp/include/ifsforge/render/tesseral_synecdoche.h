#pragma once
/// @file The tesseral synecdoche algorithm (seed 5.7, TSA): recursion with probability pruning.
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// TSA(q, lv, l, pv, p, t), with the comparison signs the seed intends (its print garbles them): a branch stops when
/// its probability p (the product of the map probabilities along its tesseral address t) falls
/// below `threshold` (pv), or at level l (options.depth if > 0); otherwise every map i appends
/// i to t, multiplies p by p_i and recurses; the leaves are plotted. pv = 0 visits every
/// branch. With depth 0 a branch also stops once its piece of the attractor fits a pixel (the
/// address tree of recursion.h; a piece smaller than a pixel that straddles pixels plots the
/// images of a few attractor points spread over it). A branch pruned by probability plots the
/// image of the start point with all its probability, so low-measure regions get fewer points,
/// as the seed intends. Raster: the measure; points = nodes visited.
class TesseralSynecdoche : public Renderer {
 public:
  std::string name() const override { return "tsa"; }
  std::string description() const override {
    return "tesseral synecdoche (5.7): recursion on tesseral addresses, pruned below a probability";
  }
  Capabilities capabilities() const override;
  std::vector<RendererParameter> parameters() const override {
    return {{"threshold", "1e-7", "pv: branches whose probability falls below this stop (0: none do)"}};
  }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

}  // namespace ifsforge
