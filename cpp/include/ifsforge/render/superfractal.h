#pragma once
/// @file Deterministic iteration for superfractals (seed 5.2.2, DIA-S): V-variable fractals.
#include "ifsforge/render/pixel_space.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// V pixel buffers start as the whole image. Each iteration builds V new buffers: for new
/// buffer v a member system Omega_n is drawn with probability P_n (Eq. 40), and each map m of
/// Omega_n is applied to a buffer drawn uniformly from the V old ones; the new buffer is the
/// union of these images (the seed's qb0 = qb0 OR w(q)). Then the new buffers replace the old
/// (qr0 = qb0; qr1 = qb1, correcting the seed's typo). Every random choice comes
/// from `seed`, so a seed names one member of the superfractal; the heavy pixel work is
/// parallel and does not depend on the thread count. An ordinary IFS is a super IFS with one
/// member: every buffer then converges to its attractor, exactly as deterministic iteration.
/// Raster: buffer `buffer` (density 1); points = map applications.
class Superfractal : public Renderer {
 public:
  std::string name() const override { return "dia-s"; }
  std::string description() const override {
    return "deterministic iteration for superfractals (5.2.2): V-variable fractals from seeded random choices";
  }
  Capabilities capabilities() const override;
  std::vector<RendererParameter> parameters() const override {
    return {{"variability", "", "V, the number of buffers (default: the system's variability, else 2)"},
            {"iterations", "", "buffer rewrites (default: until the largest copy of the image is below half a pixel)"},
            {"buffer", "0", "which of the V buffers to show"},
            supersample_parameter()};
  }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

}  // namespace ifsforge
