#pragma once
/// @file Point recursive rendering of a volume (seed 5.8.1 applied to 3D, 6.5.3.1).
#include "ifsforge/volume/volume_renderer.h"

namespace ifsforge {

/// PRR(q, L) in n dimensions over the address tree of render/recursion.h, whose node
/// (a1 ... ak) is the piece w_a1 o ... o w_ak (A) inside the box M(B). Jobs are address prefixes,
/// i.e. pieces of the attractor: each accumulates in a small dense box of voxels around its
/// piece and emits its occupied voxels sorted; the lists merge exactly.
/// options.depth = L > 0 is the seed's PRR: every leaf at depth L, plotted at the image of B's
/// centre, so a leaf of a grid-aligned system (Menger sponge at 3^L voxels a side) lands inside
/// its own cell, never on a cell boundary.
/// options.depth = 0 picks the depth from the resolution and stops each branch when its
/// occupancy stops changing: a piece whose box covers the interior of one voxel only (its sides
/// may lie on voxel faces, up to core/cells.h's rounding) is plotted there, at its centre (deeper
/// levels would land in the same voxel); a piece smaller than a voxel that straddles voxels
/// marks the images of a few attractor points at its corners, and is split further only while
/// a voxel its box meets is still empty (down to 1/4 voxel). Pieces up to 2 voxels stop as soon
/// as every voxel their box meets is occupied.
class PointRecursiveVolume : public VolumeRenderer {
 public:
  std::string name() const override { return "prr"; }
  std::string description() const override {
    return "point recursive rendering (5.8.1): deterministic, parallel over address prefixes";
  }
  Capabilities capabilities() const override;

 protected:
  Volume draw(const Ifs& ifs, const VolumeOptions& options) const override;
  std::string draw_jobs(const Ifs& ifs, const VolumeOptions& options, std::uint64_t first,
                        std::uint64_t last) const override;
};

}  // namespace ifsforge
