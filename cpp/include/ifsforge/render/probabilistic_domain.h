#pragma once
/// @file The vector recurrent probabilistic domain algorithm (seed 5.12.2).
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// N trees, one per piece A_j of a recurrent IFS. The root of tree j is A_j with weight m_j
/// (the stationary distribution). A node is a map M and a piece s standing for M(A_s); its
/// children are M o w_s (A_i) for every i that may precede s (P(i, s) > 0), with the weight
/// multiplied by r(s, i) = m_i P(i, s) / m_s (Eq. 73), so that a leaf at level t carries
/// m_j r(j, i1) ... r(i_{t-1}, i_t), the mass the measure puts on it. The leaves of tree j
/// summed per pixel make image I_j (Eq. 74). A node is a leaf at options.depth (when > 0) or
/// once its children's box M o w_s (B) fits a pixel; then its children together are its own
/// piece M(A_s), which plots M(x_s), x_s a point of A_s (a piece smaller than a pixel that may
/// straddle pixels plots the images of a few points spread over A_s). An ordinary IFS is the
/// recurrent IFS with P(i, j) = p_j. Raster: the measure of component `component` (default:
/// all trees); points = nodes expanded.
class ProbabilisticDomain : public Renderer {
 public:
  std::string name() const override { return "probabilistic-domain"; }
  std::string description() const override {
    return "vector recurrent probabilistic domain (5.12.2): one weighted address tree per piece of a recurrent IFS";
  }
  Capabilities capabilities() const override;
  std::vector<RendererParameter> parameters() const override {
    return {{"component", "", "render only tree j (image I_j, 0-based); default: every tree"}};
  }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

}  // namespace ifsforge
