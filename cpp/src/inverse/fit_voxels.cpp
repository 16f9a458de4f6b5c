#include "fit_voxels.h"

#include <algorithm>
#include <cmath>

#include "fit_shared.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/orbit.h"

namespace ifsforge {

FitVoxelGrid FitVoxelGrid::for_target(const VoxelSet& full, int raster) {
  FitVoxelGrid g;
  const int side = std::max({full.grid.dims[0], full.grid.dims[1], full.grid.dims[2]});
  g.grid.origin = full.grid.origin;
  g.grid.voxel_size = full.grid.voxel_size * side / raster;
  for (int a = 0; a < 3; ++a)
    g.grid.dims[a] = std::max(1, static_cast<int>(std::ceil(double(full.grid.dims[a]) * raster / side - 1e-9)));
  return g;
}

VoxelSet FitVoxelGrid::downsample(const VoxelSet& full) const {
  VoxelSet out{grid, std::vector<std::uint8_t>(std::size_t(grid.dims[0]) * grid.dims[1] * grid.dims[2])};
  const double f = full.grid.voxel_size / grid.voxel_size;
  auto cell = [&](int v, int a) { return std::min(grid.dims[a] - 1, static_cast<int>((v + 0.5) * f)); };
  for (int k = 0; k < full.grid.dims[2]; ++k)
    for (int j = 0; j < full.grid.dims[1]; ++j)
      for (int i = 0; i < full.grid.dims[0]; ++i)
        if (full.cells[full.index(i, j, k)]) out.cells[out.index(cell(i, 0), cell(j, 1), cell(k, 2))] = 1;
  return out;
}

VoxelMap FitVoxelGrid::voxel_map(const AffineMap& m) const {
  // P(x) = (x - origin) / h; the voxel map is P o w o P^-1: M = A, t = (A origin + b - origin) / h.
  VoxelMap v{};
  for (int r = 0; r < 3; ++r) {
    double t = m.b(r) - grid.origin[r];
    for (int c = 0; c < 3; ++c) v[r * 4 + c] = m.a(r, c), t += m.a(r, c) * grid.origin[c];
    v[r * 4 + 3] = t / grid.voxel_size;
  }
  return v;
}

VoxelCollageProxy::VoxelCollageProxy(const VoxelSet& target, double overlap_weight)
    : target_(target), overlap_weight_(overlap_weight) {
  const auto& d = target.grid.dims;
  pad_ = std::max({d[0], d[1], d[2]}) / 2;
  VoxelSet padded;
  for (int a = 0; a < 3; ++a) padded_[a] = padded.grid.dims[a] = d[a] + 2 * pad_;
  padded.cells.assign(std::size_t(padded_[0]) * padded_[1] * padded_[2], 0);
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
        if (target.cells[target.index(i, j, k)]) {
          padded.cells[padded.index(i + pad_, j + pad_, k + pad_)] = 1;
          target_cells_.push_back(static_cast<std::uint32_t>(target.index(i, j, k)));
          for (float sz : {0.25f, 0.75f})
            for (float sy : {0.25f, 0.75f})
              for (float sx : {0.25f, 0.75f}) samples_.push_back({i + sx, j + sy, k + sz});
        }
  distance_to_target_ = squared_distance_transform(padded);
  for (double& v : distance_to_target_) v = std::sqrt(v);
}

std::size_t VoxelCollageProxy::padded_cell(const VoxelMap& m, const std::array<float, 3>& p) const {
  int v[3];
  for (int r = 0; r < 3; ++r) {
    const double q = m[r * 4] * p[0] + m[r * 4 + 1] * p[1] + m[r * 4 + 2] * p[2] + m[r * 4 + 3] + pad_;
    v[r] = static_cast<int>(std::clamp(q, 0.0, padded_[r] - 1.0));
  }
  return (std::size_t(v[2]) * padded_[1] + v[1]) * padded_[0] + v[0];
}

double VoxelCollageProxy::operator()(const std::vector<VoxelMap>& maps, Scratch& s) const {
  s.stamp.assign(distance_to_target_.size(), 0);
  std::size_t cells = 0, overlap = 0;
  double outside = 0;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const auto mark = static_cast<std::uint16_t>(i + 1);
    for (const auto& p : samples_) {
      const std::size_t c = padded_cell(maps[i], p);
      auto& st = s.stamp[c];
      if (st == mark) continue;
      if (st == 0) ++cells, outside += distance_to_target_[c];
      else ++overlap;
      st = mark;
    }
  }
  // As in 2D: mean distance of the collage to the target plus of the target to the collage.
  const auto& d = target_.grid.dims;
  s.collage.grid = target_.grid;
  s.collage.cells.assign(target_.cells.size(), 0);
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
        s.collage.cells[target_.index(i, j, k)] =
            s.stamp[(std::size_t(k + pad_) * padded_[1] + j + pad_) * padded_[0] + i + pad_] != 0;
  const auto dt = squared_distance_transform(s.collage);
  double uncovered = 0;
  for (std::uint32_t c : target_cells_) uncovered += std::sqrt(dt[c]);
  const double n = static_cast<double>(target_cells_.size());
  if (!std::isfinite(uncovered)) uncovered = n * padded_[0];
  return outside / std::max<std::size_t>(cells, 1) + uncovered / n + overlap_weight_ * overlap / n;
}

double VoxelCollageProxy::copy_outside(const VoxelMap& m) const {
  double sum = 0;
  for (const auto& p : samples_) sum += distance_to_target_[padded_cell(m, p)];
  return sum / std::max<std::size_t>(samples_.size(), 1);
}

double chaos_iou_3d(const std::vector<VoxelMap>& maps, const std::vector<double>& probabilities, const VoxelSet& target,
                    std::uint64_t seed, VoxelCollageProxy::Scratch& s) {
  const auto& d = target.grid.dims;
  s.hits.assign(target.cells.size(), 0);
  const MapChain chain(probabilities);  // the one walker (a fitted system has no transitions)
  // 32 points per target voxel: the attractor, if it matches, is covered about that densely
  // (Eq. 44's points per pixel, per voxel).
  const std::uint64_t points = 32 * std::max<std::size_t>(target.count(), 256);
  Rng rng(seed, 0x10F);
  std::uint32_t state = chain.start(rng);
  double p[3] = {0.5 * d[0], 0.5 * d[1], 0.5 * d[2]};
  std::uint64_t out = 0;
  for (std::uint64_t n = 0; n < points + 64; ++n) {
    const VoxelMap& m = maps[state = chain.next(state, rng.next())];
    double q[3];
    for (int r = 0; r < 3; ++r) q[r] = m[r * 4] * p[0] + m[r * 4 + 1] * p[1] + m[r * 4 + 2] * p[2] + m[r * 4 + 3];
    std::copy(q, q + 3, p);
    if (n < 64) continue;  // contractions of at most 0.9: 64 steps forget the start
    if (p[0] >= 0 && p[1] >= 0 && p[2] >= 0 && p[0] < d[0] && p[1] < d[1] && p[2] < d[2])
      s.hits[target.index(int(p[0]), int(p[1]), int(p[2]))] = 1;
    else
      ++out;
  }
  return hits_iou(s.hits, target.cells, points, out);
}

}  // namespace ifsforge
