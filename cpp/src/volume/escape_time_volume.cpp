#include "ifsforge/volume/escape_time_volume.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "ifsforge/core/cells.h"
#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {
namespace {

/// x -> m x + t on the spatial coordinates.
struct Affine3 {
  double m[3][3], t[3];

  void apply(const double* x, double* y) const {
    for (int r = 0; r < 3; ++r) y[r] = m[r][0] * x[0] + m[r][1] * x[1] + m[r][2] * x[2] + t[r];
  }
  /// (*this) o inner.
  Affine3 after(const Affine3& inner) const {
    Affine3 out;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        out.m[r][c] = m[r][0] * inner.m[0][c] + m[r][1] * inner.m[1][c] + m[r][2] * inner.m[2][c];
      out.t[r] = m[r][0] * inner.t[0] + m[r][1] * inner.t[1] + m[r][2] * inner.t[2] + t[r];
    }
    return out;
  }
  static Affine3 identity() { return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0, 0, 0}}; }
};

Affine3 spatial_part(const AffineMap& map) {
  Affine3 a;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) a.m[r][c] = map.a(r, c);
    a.t[r] = map.b(r);
  }
  return a;
}

/// The search of one voxel: is there an address b whose inverse f_b = w_b^-1 keeps the voxel
/// inside the attractor's box for `bound` steps? Branches are tried in the order of Eq. 56.
struct VoxelSearch {
  const std::vector<Affine3>& forward;   // w_i (spatial part)
  const std::vector<Affine3>& inverse;   // f_i = w_i^-1 (Eq. 54)
  const std::vector<Point>& witnesses;   // attractor points
  const double* box_lo;                  // the escape region: the attractor's box
  const double* box_hi;
  int bound;
  bool linear, pick_max;
  double lo[3] = {}, hi[3] = {}, center[3] = {}, half[3] = {};  // the voxel
  std::uint32_t address[4096] = {};
  int length = 0;       // of the address found
  int witness = -1;     // the attractor point found in the voxel, if any
  std::uint64_t steps = 0;

  /// In the voxel's interior: an attractor point there puts positive measure in it (every
  /// neighbourhood of an attractor point has some), one on a face may belong to the neighbour.
  bool inside_voxel(const double* p) const {
    for (int a = 0; a < 3; ++a) {
      const double margin = kCellTolerance * (hi[a] - lo[a]);
      if (!(p[a] > lo[a] + margin && p[a] < hi[a] - margin)) return false;
    }
    return true;
  }

  /// `inv` = f_b (maps the voxel to its orbit), `fwd` = w_b; `level` = |b|.
  bool search(const Affine3& inv, const Affine3& fwd, int level) {
    ++steps;
    // A witness ends the search: an attractor point mapped by w_b into the voxel.
    for (std::size_t e = 0; e < witnesses.size(); ++e) {
      double p[3];
      fwd.apply(witnesses[e].data(), p);
      if (inside_voxel(p)) {
        witness = static_cast<int>(e);
        length = level;
        return true;
      }
    }
    if (level >= bound) {  // survived the escape bound
      length = level;
      return true;
    }
    double q[3];
    inv.apply(center, q);
    struct Branch {
      double delta;
      std::uint32_t map;
      Affine3 inv;
    };
    Branch branches[64];
    int count = 0;
    for (std::uint32_t i = 0; i < inverse.size(); ++i) {
      const Affine3 next = inverse[i].after(inv);
      // The orbit of the voxel under f_i o f_b: escaped when its box misses the region's
      // interior (a voxel that only touches a face of a piece holds none of its measure).
      bool kept = true;
      double qi[3], delta = 0.0;
      next.apply(center, qi);
      for (int r = 0; r < 3 && kept; ++r) {
        const double h = std::abs(next.m[r][0]) * half[0] + std::abs(next.m[r][1]) * half[1] +
                         std::abs(next.m[r][2]) * half[2];
        const double margin = kCellTolerance * h;
        kept = qi[r] + h > box_lo[r] + margin && qi[r] - h < box_hi[r] - margin;
        delta += linear ? std::abs(qi[r] - q[r]) : (qi[r] - q[r]) * (qi[r] - q[r]);  // Eq. 55
      }
      if (!kept) continue;
      Branch b{delta, i, next};
      int k = count++;
      for (; k > 0 && (pick_max ? branches[k - 1].delta < delta : branches[k - 1].delta > delta); --k)
        branches[k] = branches[k - 1];
      branches[k] = b;
    }
    for (int k = 0; k < count; ++k) {
      address[level] = branches[k].map;
      if (search(branches[k].inv, fwd.after(forward[branches[k].map]), level + 1)) return true;
    }
    return false;
  }
};

}  // namespace

Capabilities EscapeTimeVolume::capabilities() const {
  // Inverse maps from every voxel: any map may precede any other.
  using C = Capabilities;
  return {C::AverageContractive | C::Overlapping | C::Space};
}

Volume EscapeTimeVolume::draw(const Ifs& ifs, const VolumeOptions& options) const {
  if (options.distribute) run_jobs(ifs, options, 0, 0);  // InputError: no independent jobs
  const VolumeSetup setup = prepare_volume(ifs, options);
  if (options.density == VolumeDensity::Measure)
    throw InputError("escape time (5.5) finds which voxels the attractor occupies, not its measure: "
                     "use density 'binary' or 'hits', or another algorithm");
  if (ifs.size() > 64) throw InputError("escape time (5.5) handles at most 64 maps");
  const VoxelGrid& grid = setup.grid;
  if (grid.cells() > 4294967296.0)
    throw InputError("escape time (5.5) tests every voxel of the grid, and a " + std::to_string(grid.dims[0]) + "x" +
                     std::to_string(grid.dims[1]) + "x" + std::to_string(grid.dims[2]) +
                     " grid has more than 2^32; use prr or a smaller --res");
  const int n = ifs.dim();
  const int channels = n - 3;
  // Rows' lists, then their merge and the volume: refused before the first voxel.
  const double per_voxel = 2.0 * VoxelList::entry_bytes(channels) + 12.0 + 4.0 * channels;
  check_memory(expected_voxels(ifs, options, setup, per_voxel, 0.0) * per_voxel,
               "escape time (5.5) on a " + std::to_string(grid.dims[0]) + "x" + std::to_string(grid.dims[1]) + "x" +
                   std::to_string(grid.dims[2]) + " grid");
  std::vector<Affine3> forward, inverse;
  double slowest = 0.0;
  for (std::size_t i = 0; i < ifs.size(); ++i) {
    const AffineMap& m = ifs.map(i);
    const std::string which = "map " + std::to_string(i + 1);
    for (int r = 0; r < 3; ++r)
      for (int c = 3; c < n; ++c)
        if (m.a(r, c) != 0.0)
          throw InputError("escape time (5.5) needs spatial maps that do not read the other channels, but " +
                           which + " moves x, y or z by '" + ifs.layout().names()[c] + "'; use prr, ria or dia");
    AffineMap spatial(3);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) spatial.a(r, c) = m.a(r, c);
      spatial.b(r) = m.b(r);
    }
    const auto inv = spatial.inverse();
    if (!inv || !inv->finite() || std::abs(spatial.determinant()) < 1e-12)
      throw InputError("escape time (5.5) runs the inverse maps (Eq. 54), but " + which +
                       " has a singular spatial part; use prr, ria or dia");
    forward.push_back(spatial_part(m));
    inverse.push_back(spatial_part(*inv));
    slowest = std::max(slowest, spatial.contraction_factor());
  }
  double box_lo[3], box_hi[3], diagonal = 0.0;
  for (int a = 0; a < 3; ++a) {
    box_lo[a] = setup.center[a] - setup.half[a];
    box_hi[a] = setup.center[a] + setup.half[a];
    diagonal += 4.0 * setup.half[a] * setup.half[a];
  }
  diagonal = std::sqrt(diagonal);
  // Default bound: the steps after which the pieces w_b(B) are below 1/16 voxel, so that a
  // voxel surviving without a witness lies that close to the attractor. Witnesses end most
  // searches well before the bound, so the deep bound costs little.
  int bound = options.escape_bound;
  if (bound <= 0) {
    bound = 64;
    if (slowest > 0.0 && slowest < 1.0)
      bound = static_cast<int>(std::ceil(std::log(grid.voxel_size / 16.0 / diagonal) / std::log(slowest)));
    bound = std::clamp(bound, 1, 64);
  }
  if (bound > 4096) throw InputError("the escape-time bound must be at most 4096, got " + std::to_string(bound));

  const std::size_t rows = grid.dims[0];
  std::vector<VoxelList> lists(rows, VoxelList(channels));
  std::vector<std::uint64_t> steps(rows, 0);
  const Affine3 identity = Affine3::identity();
  parallel_jobs(rows, setup.threads, [&](std::size_t i, int) {
    VoxelList& out = lists[i];
    auto search = std::make_unique<VoxelSearch>(VoxelSearch{forward, inverse, setup.extremes, box_lo, box_hi, bound,
                                                            options.escape_norm == EscapeNorm::Linear,
                                                            options.escape_pick_max});
    std::vector<std::uint64_t> values(channels);
    Point p{}, q{};
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int k = 0; k < grid.dims[2]; ++k) {
        VoxelSearch& s = *search;
        const auto c = grid.center(static_cast<int>(i), j, k);
        for (int a = 0; a < 3; ++a) {
          s.center[a] = c[a];
          s.half[a] = 0.5 * grid.voxel_size;
          s.lo[a] = c[a] - s.half[a];
          s.hi[a] = c[a] + s.half[a];
        }
        bool outside = false;
        for (int a = 0; a < 3; ++a) outside = outside || s.hi[a] < box_lo[a] || s.lo[a] > box_hi[a];
        s.witness = -1;
        if (outside || !s.search(identity, identity, 0)) continue;
        // The channels of the attractor point found in the voxel (the witness mapped along the
        // address), or of the piece the voxel survived in (B's centre mapped along it).
        if (s.witness >= 0)
          p = setup.extremes[s.witness];
        else
          std::copy(setup.center.begin(), setup.center.end(), p.begin());
        for (int level = s.length - 1; level >= 0 && channels; --level) {
          ifs.map(s.address[level]).apply(p.data(), q.data());
          p = q;
        }
        for (int ch = 0; ch < channels; ++ch) values[ch] = setup.quantizer.quantize(ch, p[3 + ch]);
        out.push(VoxelGrid::key(i, j, k), 1, 0, values.data());
      }
    steps[i] = search->steps;
  }, progress_range(options.progress, 0.0, 0.95));
  Volume volume = finish_volume(lists, grid, ifs, setup.quantizer, options.density, kVolumeMassUnit, setup.threads);
  volume.algorithm = name();
  volume.depth = bound;
  for (std::uint64_t s : steps) volume.points += s;
  if (options.progress && !options.progress(1.0)) throw Cancelled();
  return volume;
}

}  // namespace ifsforge
