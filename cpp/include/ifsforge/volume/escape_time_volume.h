#pragma once
/// @file The escape-time algorithm for IFS volumes (seed 5.5, Eq. 54-56).
#include "ifsforge/volume/volume_renderer.h"

namespace ifsforge {

/// Runs the shift dynamical system f_i = w_i^-1 (Eq. 54) on every voxel, carried as a box (its
/// image under the composed inverse maps): the orbit escapes when that box leaves the
/// attractor's box B. Branches are tried in the order of Eq. 55-56's delta between the voxel
/// centre's orbit point and its image (Euclidean or linear; smallest first, or largest), and a
/// failed branch gives way to the next. A voxel belongs to the attractor when some branch
/// survives `escape_bound` steps (default: until the pieces w_b(B) are below 1/16 voxel), or
/// earlier when a witness is found: an attractor point mapped by w_b into the voxel. The
/// voxel's channels are those of that point (or of B's centre mapped along the address).
/// Needs invertible spatial parts that do not read the other channels.
class EscapeTimeVolume : public VolumeRenderer {
 public:
  std::string name() const override { return "eta"; }
  std::string description() const override {
    return "escape-time algorithm (5.5): inverse maps from every voxel, delta-norm choice";
  }
  Capabilities capabilities() const override;

 protected:
  Volume draw(const Ifs& ifs, const VolumeOptions& options) const override;
};

}  // namespace ifsforge
