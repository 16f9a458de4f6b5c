#pragma once
/// @file Random iteration (seed 5.1.1): the chaos game, into a hit histogram.
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// Work is cut into jobs of 2^22 points, each with its own random stream derived from
/// (seed, job): the image depends on the seed and the point count, never on the threads.
/// Purely spatial 2D and 3D systems with at most 8 maps take the lane kernels (32 games at
/// once in single precision, iterating directly in pixel coordinates: the maps are conjugated
/// by the world-to-pixel transform), picked at run time for the CPU and giving the same bytes
/// on every one; systems with polar maps (3.3.3) a scalar path that applies them; everything
/// else the general nD path.
class ChaosGame : public Renderer {
 public:
  std::string name() const override { return "chaos"; }
  std::string description() const override {
    return "random iteration algorithm (5.1.1): density histogram of the chaos game";
  }
  Capabilities capabilities() const override;
  bool distributable() const override { return true; }

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
  /// Jobs' histograms as sparse tiles of integer sums (Accumulator::encode).
  std::string draw_jobs(const Ifs& ifs, const RenderOptions& options, std::uint64_t first,
                        std::uint64_t last) const override;
};

}  // namespace ifsforge
