#include "ifsforge/volume/point_recursive_volume.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "ifsforge/core/cells.h"
#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/recursion.h"
#include "ifsforge/volume/volume_jobs.h"
#include "ifsforge/volume/voxel_accumulator.h"

namespace ifsforge {
namespace {

/// A piece whose box spans at least this many voxels is split (unless all it meets is occupied).
constexpr double kSplitAbove = 1.0;
/// Pieces below this many voxels stop as soon as every voxel their box meets is occupied
/// (3: 7% faster than 2 on the 512^3 pyramid, the same voxels).
constexpr double kCheckBelow = 3.0;
/// A straddling piece below this many voxels is not split further. 1/4 finds 98% of the voxels
/// the attractor meets at 2/3 of the cost of 1/16 (6D pyramid at 256^3: 668,216 of 682,836).
constexpr double kFinest = 1.0 / 4.0;

/// The leaves of `depth` more levels below a node, relative to the node: the images of
/// `start` under every address of that length, with their masses. Plotting M(s) for each s
/// is the same as walking those levels below a node with composed map M, without composing.
struct Cloud {
  std::vector<Point> points;
  std::vector<double> mass;
};

Cloud suffix_cloud(const Ifs& ifs, const Point& start, int depth) {
  Cloud cloud;
  if (depth <= 0) {
    cloud.points.push_back(start);
    cloud.mass.push_back(1.0);
    return cloud;
  }
  RecursionPlan plan;
  plan.max_depth = depth;
  walk_job(ifs, plan, 0, [](const RecursionNode&) { return false; }, [&](const RecursionNode& node) {
    cloud.points.push_back(node.map(start));
    cloud.mass.push_back(node.mass);
  });
  return cloud;
}

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

SubTree build_subtree(const Ifs& ifs, const RecursionPlan& plan, const std::vector<Point>& reps,
                      const Point& center, int levels) {
  SubTree t;
  t.dim = ifs.dim();
  t.reps = static_cast<int>(reps.size());
  std::vector<AffineMap> maps{AffineMap(ifs.dim())};
  std::vector<double> masses{1.0};
  std::vector<int> depth{0};
  // Breadth first, so that the children of node k are contiguous.
  for (std::size_t k = 0; k < maps.size(); ++k) {
    if (depth[k] == levels) {
      t.first_child.push_back(0);
      continue;
    }
    t.first_child.push_back(static_cast<std::uint32_t>(maps.size()));
    for (std::size_t i = 0; i < ifs.size(); ++i) {
      maps.push_back(maps[k].compose(ifs.map(i)));
      masses.push_back(masses[k] * ifs.probabilities()[i]);
      depth.push_back(depth[k] + 1);
    }
  }
  for (std::size_t k = 0; k < maps.size(); ++k) {
    std::vector<double> c(t.dim), h(t.dim);
    image_box(maps[k], plan, t.dim, c.data(), h.data());
    t.center.insert(t.center.end(), c.begin(), c.end());
    t.half.insert(t.half.end(), h.begin(), h.end());
    const Point f = maps[k](center);
    t.focus.insert(t.focus.end(), f.begin(), f.begin() + t.dim);
    for (const Point& e : reps) {
      const Point q = maps[k](e);
      t.points.insert(t.points.end(), q.begin(), q.begin() + t.dim);
    }
  }
  t.mass = masses;
  t.level = depth;
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
    if (weigh) acc.add_voxel(marked, nullptr, piece, false);
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

std::unique_ptr<Expander> make_expander(int dim, bool spatial, const SubTree& t, const VoxelGrid& g,
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

/// True when no spatial row of any map reads a non-spatial channel.
bool spatial_rows_independent(const Ifs& ifs) {
  for (const auto& m : ifs.maps())
    for (int r = 0; r < 3; ++r)
      for (int c = 3; c < ifs.dim(); ++c)
        if (m.a(r, c) != 0.0) return false;
  return true;
}

/// The jobs of one render: its setup and address-prefix plan, and per job run, the sorted
/// voxels (or, when encoded, the job bytes holding them), the points plotted and the depth
/// reached.
struct PrrJobs {
  VolumeSetup setup;
  std::uint64_t jobs = 0;
  std::vector<VoxelList> lists;
  std::vector<std::string> encoded;
  std::vector<std::uint64_t> leaves;
  std::vector<int> deepest;
};

/// Plans the render and runs its jobs [first, last) (clamped to the job count; none when
/// first >= last: the plan alone, for a render whose jobs run elsewhere). `encode`: each job's
/// voxels kept as job bytes (encode_volume_jobs, a few bytes per voxel instead of 24 or more),
/// to be merged slab by slab as a cluster's results are.
PrrJobs point_recursive_jobs(const Ifs& ifs, const VolumeOptions& options, std::uint64_t first, std::uint64_t last,
                             const ProgressCallback& progress, bool encode) {
  PrrJobs out;
  out.setup = prepare_volume(ifs, options);
  const VolumeSetup& setup = out.setup;
  const VoxelGrid& grid = setup.grid;
  const std::size_t n = ifs.size();
  const int dim = ifs.dim();
  const double log_n = std::log(std::max<double>(2.0, static_cast<double>(n)));
  const bool fixed = options.depth > 0;
  if (fixed) check_leaf_count(n, options.depth);

  RecursionPlan plan;
  plan.center = setup.center;
  plan.half = setup.half;
  Point center{};
  std::copy(setup.center.begin(), setup.center.end(), center.begin());
  double shrink = 0.0;
  for (double s : ifs.spatial_contraction_factors()) shrink = std::max(shrink, s);

  // Fixed depth L (the seed's PRR): walk L - d levels and plot, below each node, the cloud of
  // the d last levels. Automatic: the walk stops at pieces of a few voxels, whose sub-tree
  // (precomputed, `levels` deep) finishes the job with the stop rules of the header; the
  // walk's depth is capped where the least contractive branch shrinks B below kFinest voxels
  // (Eq. 59's N^L >= cells when some map does not contract).
  Cloud cloud;
  SubTree tree;
  int cloud_levels = 0, tree_levels = 0;
  double handover = 0.0;  // pieces up to this many voxels go to the sub-tree
  if (fixed) {
    cloud_levels = n < 2 ? 0 : std::min(options.depth - 1, static_cast<int>(std::log(256.0) / log_n));
    plan.max_depth = options.depth - cloud_levels;
    cloud = suffix_cloud(ifs, center, cloud_levels);
  } else {
    const int eq59 = n < 2 ? 1 : static_cast<int>(std::ceil(std::log(grid.cells()) / log_n));
    plan.max_depth = depth_for_size(ifs, plan, grid.voxel_size * kFinest, 1, eq59);
    tree_levels = std::max(1, static_cast<int>(std::log(1024.0) / log_n));  // about a thousand nodes
    if (shrink > 0.0 && shrink < 1.0) handover = kFinest * std::pow(1.0 / shrink, tree_levels);
    tree = build_subtree(ifs, plan, setup.extremes, center, tree_levels);
  }

  // Jobs: address prefixes whose pieces of the attractor span at most ~16 voxels, so that
  // each accumulates in a small dense box (in cache); at least 64 of them for load balance,
  // at most 2^15 (a system with one weakly contracting map would otherwise ask for millions
  // of jobs, each walking its prefix).
  double side = std::max({grid.dims[0], grid.dims[1], grid.dims[2]});
  while (n > 1 && plan.prefix < plan.max_depth && plan.jobs * n <= (1u << 15) &&
         (plan.jobs < 64 || (shrink < 1.0 && side > 16.0))) {
    ++plan.prefix;
    plan.jobs *= n;
    side *= shrink;
  }

  const int channels = dim - 3;
  // Each voxel about twice over the jobs' lists or bytes (a varint key delta, hits, mass and
  // 3-byte channel sums at most), then once in the volume.
  const double kept = encode ? 4.0 + (options.density == VolumeDensity::Measure ? 9.0 : 0.0) + 3.0 * channels
                             : VoxelList::entry_bytes(channels);
  const double per_voxel = 2.0 * kept + 12.0 + 4.0 * channels;
  const double scratch_bytes = setup.threads * VoxelAccumulator::bytes(channels);
  double expected = expected_voxels(ifs, options, setup, per_voxel, scratch_bytes);
  if (fixed) expected = std::min(expected, std::pow(static_cast<double>(n), options.depth));  // the leaves
  // A cluster worker running a range of the jobs holds their share of the voxels only; a
  // render merging a cluster's results (no jobs here) checks the voxels it receives instead.
  out.jobs = plan.jobs;
  last = std::min<std::uint64_t>(last, plan.jobs);
  const std::uint64_t count = last > first ? last - first : 0;
  if (count == 0) return out;
  const bool part = count < plan.jobs;
  const double share = part ? static_cast<double>(count) / static_cast<double>(plan.jobs) : 1.0;
  check_memory(share * expected * per_voxel + scratch_bytes,
               "a " + std::to_string(options.resolution) + "^3 point-recursive volume" +
                   (part ? " (jobs " + std::to_string(first) + ".." + std::to_string(last - 1) + ")" : ""));
  std::vector<VoxelAccumulator> scratch(std::min<std::uint64_t>(setup.threads, count),
                                        VoxelAccumulator(grid, setup.quantizer));
  std::vector<VoxelList>& lists = out.lists;
  std::vector<std::uint64_t>& leaves = out.leaves;
  std::vector<int>& deepest = out.deepest;
  lists.assign(encode ? 0 : count, VoxelList(channels));
  out.encoded.assign(encode ? count : 0, std::string());
  leaves.assign(count, 0);
  deepest.assign(count, 0);
  const double inverse = 1.0 / grid.voxel_size;
  const bool spatial = spatial_rows_independent(ifs);
  // The box M(centre +- half) in continuous voxel coordinates.
  auto voxel_box = [&](const AffineMap& m, const double* c0, const double* h0, double* lo, double* hi) {
    for (int a = 0; a < 3; ++a) {
      double c = m.b(a), h = 0.0;
      for (int k = 0; k < dim; ++k) {
        c += m.a(a, k) * c0[k];
        h += std::abs(m.a(a, k)) * h0[k];
      }
      lo[a] = (c - h - grid.origin[a]) * inverse;
      hi[a] = (c + h - grid.origin[a]) * inverse;
    }
  };
  auto misses = [&](const double* lo, const double* hi) {
    for (int a = 0; a < 3; ++a)
      if (hi[a] < 0.0 || lo[a] >= grid.dims[a]) return true;
    return false;
  };

  parallel_jobs(
      count, static_cast<int>(scratch.size()),
      [&](std::size_t index, int worker) {
        const std::uint64_t job = first + index;
        VoxelAccumulator& acc = scratch[worker];
        // The job's piece of the attractor: the prefix map applied to B.
        AffineMap prefix(dim);
        std::vector<std::uint32_t> digits(plan.prefix);
        std::uint64_t rest = job;
        for (int level = plan.prefix - 1; level >= 0; --level) {
          digits[level] = static_cast<std::uint32_t>(rest % n);
          rest /= n;
        }
        for (std::uint32_t d : digits) prefix = prefix.compose(ifs.map(d));
        double lo[3], hi[3];
        voxel_box(prefix, plan.center.data(), plan.half.data(), lo, hi);
        acc.begin(lo, hi);
        std::uint64_t plotted = 0;
        int depth = 0;
        Point q;
        std::unique_ptr<Expander> expander;
        if (!fixed) expander = make_expander(dim, spatial, tree, grid, acc, n, options.density == VolumeDensity::Measure);

        auto stop = [&](const RecursionNode& node) {
          double l[3], h[3];
          voxel_box(node.map, plan.center.data(), plan.half.data(), l, h);
          if (misses(l, h)) return true;
          if (fixed) return false;
          // The sub-tree finishes pieces up to `handover`, and any piece below kFinest (some
          // systems have no handover: a map that stretches leaves no size the sub-tree is
          // sure to resolve, yet most pieces shrink).
          const double extent = std::max({h[0] - l[0], h[1] - l[1], h[2] - l[2]});
          return extent <= std::max(handover, kFinest) || (extent < kCheckBelow && acc.occupied(l, h));
        };
        walk_job(ifs, plan, job, stop, [&](const RecursionNode& node) {
          if (!fixed) {
            expander->run(node.map, node.mass, node.length);
            return;
          }
          double l[3], h[3];
          voxel_box(node.map, plan.center.data(), plan.half.data(), l, h);
          if (misses(l, h)) return;
          for (std::size_t k = 0; k < cloud.points.size(); ++k) {
            node.map.apply(cloud.points[k].data(), q.data());
            acc.add(q.data(), node.mass * cloud.mass[k]);
          }
          plotted += cloud.points.size();
          depth = std::max(depth, node.length + cloud_levels);
        });
        leaves[index] = plotted + (expander ? expander->plotted() : 0);
        deepest[index] = std::max(depth, expander ? expander->depth() : 0);
        if (encode) {
          VolumeJobsResult result;
          result.voxels = acc.finish();
          result.points = leaves[index];
          result.depth = deepest[index];
          out.encoded[index] = encode_volume_jobs(result, options.density);
        } else {
          lists[index] = acc.finish();
        }
      },
      progress);
  return out;
}

}  // namespace

Volume PointRecursiveVolume::render(const Ifs& ifs, const VolumeOptions& options) const {
  // Here or on a cluster, the jobs' voxels end as job bytes merged slab by slab, so that only
  // the volume is ever built whole.
  const bool here = !options.distribute;
  PrrJobs run = point_recursive_jobs(ifs, options, 0, here ? ~std::uint64_t(0) : 0,
                                     progress_range(options.progress, 0.0, 0.9), true);
  const std::vector<std::string_view> results =
      here ? std::vector<std::string_view>(run.encoded.begin(), run.encoded.end()) : options.distribute(0, run.jobs);
  std::vector<VolumeJobsBytes> parts(results.begin(), results.end());
  if (!here) {
    double entries = 0.0;
    for (const VolumeJobsBytes& part : parts) entries += static_cast<double>(part.entries());
    check_memory(entries * (12.0 + 4.0 * (ifs.dim() - 3)),
                 "merging a " + std::to_string(options.resolution) + "^3 point-recursive volume");
  }
  if (options.progress && !options.progress(0.95)) throw Cancelled();
  const VolumeSetup& setup = run.setup;
  Volume volume = finish_volume_jobs(parts, setup.grid, ifs, setup.quantizer, options.density, kVolumeMassUnit,
                                     setup.threads);
  volume.algorithm = name();
  for (const VolumeJobsBytes& part : parts) {
    volume.depth = std::max(volume.depth, part.depth());
    volume.points += part.points();
  }
  if (options.progress && !options.progress(1.0)) throw Cancelled();
  return volume;
}

std::string PointRecursiveVolume::run_jobs(const Ifs& ifs, const VolumeOptions& options, std::uint64_t first,
                                           std::uint64_t last) const {
  PrrJobs run = point_recursive_jobs(ifs, options, first, last, options.progress, false);
  int depth = 0;
  std::uint64_t points = 0;
  for (int d : run.deepest) depth = std::max(depth, d);
  for (std::uint64_t l : run.leaves) points += l;
  return encode_volume_jobs(run.lists, points, depth, options.density, run.setup.threads);
}

}  // namespace ifsforge
