#pragma once
/// @file Deterministic iteration by volume rewriting (seed 5.2.1, Eq. 49-51, in 3D).
#include "ifsforge/volume/volume_renderer.h"

namespace ifsforge {

/// Starts from the whole grid holding a uniform measure (Eq. 49) and applies the Markov
/// operator (Eq. 50): every occupied voxel sends p_i of its mass, and its points mapped by w_i
/// (channels included), to the voxels holding their images. A voxel keeps, of the points it
/// receives, the six extreme along +-x, +-y, +-z (its centre at the start) and the mean of
/// their channels, as exact integer merges. Mapping these exact images rather than the voxel
/// centre keeps rounding from accumulating (Eq. 53's drift would thicken thin attractors by a
/// voxel or more). Rewriting stops when occupancy stops changing (the occupied count moves by
/// less than 0.1% from one level to the next: the stationary state of Eq. 51 on the grid), or
/// after options.depth levels.
class DeterministicIterationVolume : public VolumeRenderer {
 public:
  std::string name() const override { return "dia"; }
  std::string description() const override {
    return "deterministic iteration algorithm (5.2.1): volume rewriting by the Markov operator";
  }
  Capabilities capabilities() const override;

 protected:
  Volume draw(const Ifs& ifs, const VolumeOptions& options) const override;
};

}  // namespace ifsforge
