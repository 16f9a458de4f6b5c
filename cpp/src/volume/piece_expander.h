#pragma once
/// @file Point recursive volumes at automatic depth (seed 5.13.2): the address tree's last
/// levels below a node, computed once per render (SubTree) and evaluated per node in the
/// system's dimension with fixed-size products (PieceExpander), into a job's VoxelAccumulator.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "ifsforge/core/cells.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/render/recursion.h"
#include "ifsforge/volume/voxel_accumulator.h"

namespace ifsforge::prr_volume {

/// A piece whose box spans at least this many voxels is split (unless all it meets is occupied).
constexpr double kSplitAbove = 1.0;
/// Pieces below this many voxels stop as soon as every voxel their box meets is occupied
/// (the check costs more than it saves on pieces larger than this; the voxels are the same).
constexpr double kCheckBelow = 3.0;
/// A straddling piece below this many voxels is not split further: finer limits find the last
/// few voxels the attractor meets at a cost out of proportion to them.
constexpr double kFinest = 1.0 / 4.0;

/// The address tree below a node, `levels` deep, relative to the node and computed once: sub-node
/// b stores the box of w_b(B) (centre and half-extent, all n dimensions), p_b, the image of B's
/// centre and of the representatives under w_b, and where its children start. At a node with
/// composed map M, the box of sub-node b is bounded by M(centre) +- |M| half, and its points are
/// M applied to the stored images: the last levels cost a few matrix-vector products per node
/// instead of composing n x n maps.
struct SubTree {
  int dim = 0, reps = 0;
  std::vector<double> center, half, focus, points;  // per node: dim, dim, dim, reps * dim
  std::vector<double> mass;
  std::vector<std::uint32_t> first_child;  // 0: the node is at the bottom
  std::vector<int> level;
};

inline SubTree build_subtree(const Ifs& ifs, const RecursionPlan& plan, const std::vector<Point>& reps,
                             const Point& center, int levels, int threads) {
  SubTree t;
  t.dim = ifs.dim();
  t.reps = static_cast<int>(reps.size());
  const std::size_t n = ifs.size(), dim = static_cast<std::size_t>(t.dim), per_node = reps.size() * dim;
  // Breadth first, so that the children of node k are contiguous: level L starts at starts[L],
  // and its node j has parent j / n of level L - 1 and map j % n. Each node depends on its parent
  // alone, so a level's nodes are made in parallel (before the volume's jobs, this ran on one
  // core), each exactly as a serial walk makes it; the arrays are sized up front (growing a
  // vector of AffineMaps, about 600 bytes each, copied them over and over).
  std::vector<std::size_t> starts{0, 1};
  for (std::size_t level = 0, width = 1; level < static_cast<std::size_t>(levels); ++level)
    starts.push_back(starts.back() + (width *= n));
  const std::size_t nodes = starts[static_cast<std::size_t>(levels) + 1];
  std::vector<AffineMap> maps(nodes);
  maps[0] = AffineMap(ifs.dim());
  t.mass.assign(nodes, 1.0);
  t.level.assign(nodes, 0);
  t.first_child.assign(nodes, 0);
  t.center.resize(nodes * dim);
  t.half.resize(nodes * dim);
  t.focus.resize(nodes * dim);
  t.points.resize(nodes * per_node);
  // Jobs of a fixed number of nodes: which thread makes a node never matters.
  constexpr std::size_t kNodesPerJob = 64;
  auto in_jobs = [&](std::size_t first, std::size_t last, auto&& make) {
    parallel_jobs((last - first + kNodesPerJob - 1) / kNodesPerJob, threads, [&](std::size_t job, int) {
      for (std::size_t k = first + job * kNodesPerJob, end = std::min(last, k + kNodesPerJob); k < end; ++k) make(k);
    });
  };
  for (int level = 1; level <= levels; ++level) {
    const std::size_t first = starts[level], parents = starts[level - 1];
    in_jobs(first, starts[level + 1], [&](std::size_t k) {
      const std::size_t j = k - first, parent = parents + j / n, i = j % n;
      maps[k] = maps[parent].compose(ifs.map(i));
      t.mass[k] = t.mass[parent] * ifs.probabilities()[i];
      t.level[k] = level;
    });
  }
  for (int level = 0; level < levels; ++level)
    for (std::size_t k = starts[level]; k < starts[level + 1]; ++k)
      t.first_child[k] = static_cast<std::uint32_t>(starts[level + 1] + (k - starts[level]) * n);
  in_jobs(0, nodes, [&](std::size_t k) {
    image_box(maps[k], plan, t.dim, &t.center[k * dim], &t.half[k * dim]);
    const Point f = maps[k](center);
    std::copy(f.begin(), f.begin() + t.dim, t.focus.begin() + k * dim);
    for (std::size_t r = 0; r < reps.size(); ++r) {
      const Point q = maps[k](reps[r]);
      std::copy(q.begin(), q.begin() + t.dim, t.points.begin() + k * per_node + r * dim);
    }
  });
  return t;
}

/// Evaluates the sub-tree below one node (automatic depth) in N dimensions, with the node's map
/// held in fixed-size arrays so that the small products unroll, its spatial rows scaled into
/// continuous voxel coordinates. `Cols` is N, or 3 when the spatial rows do not read the other
/// channels (their boxes then need the spatial block only). `weigh`: the density is the
/// measure, so every piece's mass must reach a voxel; otherwise pieces that cannot change the
/// occupancy stop without a trace.
template <int N, int Cols>
struct PieceExpander {
  PieceExpander(const SubTree& t, const VoxelGrid& g, VoxelAccumulator& accumulator, std::size_t n, bool weigh_mass)
      : center(t.center.data()), half(t.half.data()), focus(t.focus.data()), points(t.points.data()),
        mass_of(t.mass.data()), first_child(t.first_child.data()), level(t.level.data()), reps(t.reps),
        grid(g), acc(accumulator), maps(static_cast<std::uint32_t>(n)), weigh(weigh_mass) {}

  const double *center, *half, *focus, *points, *mass_of;
  const std::uint32_t* first_child;
  const int* level;
  int reps;
  const VoxelGrid& grid;
  VoxelAccumulator& acc;
  std::uint32_t maps;
  bool weigh;
  std::uint64_t plotted = 0;
  int depth = 0;
  double a[N][N] = {}, b[N] = {};

  /// y = M x on the spatial rows only: where the voxel is.
  void locate(const double* x, double* y) const {
    for (int r = 0; r < 3; ++r) {
      double v = b[r];
      for (int c = 0; c < Cols; ++c) v += a[r][c] * x[c];
      y[r] = v;
    }
  }
  /// y = M x on every row (position and channels).
  void apply(const double* x, double* y) const {
    for (int r = 0; r < N; ++r) {
      double v = b[r];
      for (int c = 0; c < (r < 3 ? Cols : N); ++c) v += a[r][c] * x[c];
      y[r] = v;
    }
  }
  /// The box M(centre +- half) of sub-node k.
  void box(std::uint32_t k, double* lo, double* hi) const {
    const double* c0 = center + k * N;
    const double* h0 = half + k * N;
    for (int r = 0; r < 3; ++r) {
      double c = b[r], h = 0.0;
      for (int col = 0; col < Cols; ++col) {
        c += a[r][col] * c0[col];
        h += std::abs(a[r][col]) * h0[col];
      }
      lo[r] = c - h;
      hi[r] = c + h;
    }
  }
  /// A point of the attractor: its voxel counts it (a hit: occupancy, channels) and gets `mass`.
  void plot(const double* point, double mass) {
    double q[N];
    apply(point, q);
    acc.add_voxel(q, q + 3, mass);
  }
  void reached(std::uint32_t k, int length) { depth = std::max(depth, length + level[k]); }

  void run(const AffineMap& m, double mass, int length) {
    const double inverse = 1.0 / grid.voxel_size;
    for (int r = 0; r < N; ++r) {
      const double scale = r < 3 ? inverse : 1.0;
      for (int c = 0; c < N; ++c) a[r][c] = m.a(r, c) * scale;
      b[r] = r < 3 ? (m.b(r) - grid.origin[r]) * inverse : m.b(r);
    }
    expand(0, mass, length);
  }

  // A piece inside one voxel is plotted there (deeper levels cannot change the occupancy). A
  // piece smaller than a voxel whose box meets only occupied voxels stops: its mass goes to
  // the voxel of its centre, which is occupied, so the voxel's channels are left as they are.
  // Otherwise the piece marks the voxels of its representatives (images of the attractor's
  // extreme points, so points of the attractor): a representative in an empty voxel is a hit,
  // one in an occupied voxel costs only its position. The piece is then split further while
  // a voxel its box meets is still empty, down to kFinest; its mass then goes to its first
  // representative's voxel.
  void expand(std::uint32_t k, double mass, int length) {
    double l[3], h[3];
    box(k, l, h);
    std::int64_t first[3], last[3];  // the voxels whose interior the box meets
    for (int r = 0; r < 3; ++r) {
      if (h[r] < 0.0 || l[r] >= grid.dims[r]) return;
      covered_cells(l[r], h[r], first[r], last[r]);
    }
    const double piece = mass * mass_of[k];
    const bool one_voxel = first[0] == last[0] && first[1] == last[1] && first[2] == last[2];
    if (one_voxel) {
      plot(focus + k * N, piece);
      ++plotted;
      reached(k, length);
      return;
    }
    const double extent = std::max({h[0] - l[0], h[1] - l[1], h[2] - l[2]});
    const std::uint32_t child = first_child[k];
    if (extent < kCheckBelow && acc.occupied(first, last)) {
      if (weigh) {
        double u[3];
        locate(focus + k * N, u);
        acc.add_voxel(u, nullptr, piece, false);
      }
      ++plotted;
      reached(k, length);
      return;
    }
    if (extent >= kSplitAbove && child) {
      for (std::uint32_t i = 0; i < maps; ++i) expand(child + i, mass, length);
      return;
    }
    double marked[3];  // the first representative
    for (int e = 0; e < reps; ++e) {
      const double* point = points + (k * reps + e) * N;
      double u[3];
      locate(point, u);
      if (e == 0) std::copy(u, u + 3, marked);
      // A point on a voxel face may belong to the neighbour (a shared corner of grid-aligned
      // pieces): only points strictly inside a voxel mark it.
      if (on_cell_edge(u[0]) || on_cell_edge(u[1]) || on_cell_edge(u[2])) continue;
      if (!acc.occupied_voxel(u)) plot(point, 0.0);
    }
    plotted += reps;
    if (child && extent >= kFinest && !acc.occupied(first, last)) {
      for (std::uint32_t i = 0; i < maps; ++i) expand(child + i, mass, length);
      return;
    }
    if (weigh) acc.add_mass(marked, first, last, piece);
    reached(k, length);
  }
};

/// Expands the sub-tree below a node in the system's dimension.
struct Expander {
  virtual ~Expander() = default;
  virtual void run(const AffineMap& m, double mass, int length) = 0;
  virtual std::uint64_t plotted() const = 0;
  virtual int depth() const = 0;
};

template <int N, int Cols>
struct FixedExpander : Expander {
  PieceExpander<N, Cols> impl;
  FixedExpander(const SubTree& t, const VoxelGrid& g, VoxelAccumulator& acc, std::size_t maps, bool weigh)
      : impl(t, g, acc, maps, weigh) {}
  void run(const AffineMap& m, double mass, int length) override { impl.run(m, mass, length); }
  std::uint64_t plotted() const override { return impl.plotted; }
  int depth() const override { return impl.depth; }
};

template <int N>
std::unique_ptr<Expander> expander_for(bool spatial, const SubTree& t, const VoxelGrid& g, VoxelAccumulator& acc,
                                       std::size_t maps, bool weigh) {
  if (spatial) return std::make_unique<FixedExpander<N, 3>>(t, g, acc, maps, weigh);
  return std::make_unique<FixedExpander<N, N>>(t, g, acc, maps, weigh);
}

inline std::unique_ptr<Expander> make_expander(int dim, bool spatial, const SubTree& t, const VoxelGrid& g,
                                        VoxelAccumulator& acc, std::size_t maps, bool weigh) {
  switch (dim) {
    case 3: return expander_for<3>(true, t, g, acc, maps, weigh);
    case 4: return expander_for<4>(spatial, t, g, acc, maps, weigh);
    case 5: return expander_for<5>(spatial, t, g, acc, maps, weigh);
    case 6: return expander_for<6>(spatial, t, g, acc, maps, weigh);
    case 7: return expander_for<7>(spatial, t, g, acc, maps, weigh);
    default: return expander_for<8>(spatial, t, g, acc, maps, weigh);
  }
}

}  // namespace ifsforge::prr_volume
