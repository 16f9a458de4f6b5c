#pragma once
/// @file Random iteration into a volume (seed 5.1.1 applied to 3D).
#include "ifsforge/volume/volume_renderer.h"

namespace ifsforge {

/// The chaos game in n dimensions; each point adds a hit (and its channel values) to its
/// voxel. Jobs of 2^20 points have their own random stream (seed, job); workers accumulate in
/// hash tables of integer sums, so the volume depends on the seed and the point count only.
/// With options.iterations = 0 the point count doubles (from 2^21) until a round adds fewer
/// than 1% new voxels, the volumetric form of Eq. 45's coupon collector.
class RandomIterationVolume : public VolumeRenderer {
 public:
  std::string name() const override { return "ria"; }
  std::string description() const override {
    return "random iteration algorithm (5.1.1): hits per voxel of the chaos game";
  }
  Capabilities capabilities() const override;

 protected:
  Volume draw(const Ifs& ifs, const VolumeOptions& options) const override;
  std::string draw_jobs(const Ifs& ifs, const VolumeOptions& options, std::uint64_t first,
                        std::uint64_t last) const override;
};

}  // namespace ifsforge
