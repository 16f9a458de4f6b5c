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
#include "piece_expander.h"

namespace ifsforge {
namespace {

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
  prr_volume::SubTree tree;
  int cloud_levels = 0, tree_levels = 0;
  double handover = 0.0;  // pieces up to this many voxels go to the sub-tree
  if (fixed) {
    cloud_levels = n < 2 ? 0 : std::min(options.depth - 1, static_cast<int>(std::log(256.0) / log_n));
    plan.max_depth = options.depth - cloud_levels;
    cloud = suffix_cloud(ifs, center, cloud_levels);
  } else {
    const int eq59 = n < 2 ? 1 : static_cast<int>(std::ceil(std::log(grid.cells()) / log_n));
    plan.max_depth = depth_for_size(ifs, plan, grid.voxel_size * prr_volume::kFinest, 1, eq59);
    tree_levels = std::max(1, static_cast<int>(std::log(1024.0) / log_n));  // about a thousand nodes
    if (shrink > 0.0 && shrink < 1.0) handover = prr_volume::kFinest * std::pow(1.0 / shrink, tree_levels);
    tree = prr_volume::build_subtree(ifs, plan, setup.extremes, center, tree_levels, setup.threads);
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
        std::unique_ptr<prr_volume::Expander> expander;
        if (!fixed) expander = prr_volume::make_expander(dim, spatial, tree, grid, acc, n, options.density == VolumeDensity::Measure);

        auto stop = [&](const RecursionNode& node) {
          double l[3], h[3];
          voxel_box(node.map, plan.center.data(), plan.half.data(), l, h);
          if (misses(l, h)) return true;
          if (fixed) return false;
          // The sub-tree finishes pieces up to `handover`, and any piece below kFinest (some
          // systems have no handover: a map that stretches leaves no size the sub-tree is
          // sure to resolve, yet most pieces shrink).
          const double extent = std::max({h[0] - l[0], h[1] - l[1], h[2] - l[2]});
          return extent <= std::max(handover, prr_volume::kFinest) || (extent < prr_volume::kCheckBelow && acc.occupied(l, h));
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

Capabilities PointRecursiveVolume::capabilities() const {
  // Pieces cut at the voxel: the address tree knows no forbidden words, and a map that
  // expands never gets below the cut (as for the image renderer).
  using C = Capabilities;
  return {C::Overlapping | C::Space};
}

Volume PointRecursiveVolume::draw(const Ifs& ifs, const VolumeOptions& options) const {
  // Here or on a cluster, the jobs' voxels end as job bytes merged slab by slab, so that only
  // the volume is ever built whole.
  const bool here = !options.distribute;
  PrrJobs run = point_recursive_jobs(ifs, options, 0, here ? ~std::uint64_t(0) : 0,
                                     progress_range(options.progress, 0.0, 0.9), true);
  const std::vector<std::string_view> results =
      here ? std::vector<std::string_view>(run.encoded.begin(), run.encoded.end()) : options.distribute(0, run.jobs);
  std::vector<VolumeJobsBytes> parts = read_volume_jobs(results, run.setup.threads);
  const VolumeSetup& setup = run.setup;
  Volume header = empty_volume(setup.grid, ifs, setup.quantizer, options.density);
  header.algorithm = name();
  for (const VolumeJobsBytes& part : parts) {
    header.depth = std::max(header.depth, part.depth());
    header.points += part.points();
  }
  if (options.progress && !options.progress(0.95)) throw Cancelled();
  if (options.bands) {  // a band at a time: nothing more is held
    give_volume_jobs(parts, header, setup.quantizer, kVolumeMassUnit, options.bands);
  } else {
    if (!here) {
      double entries = 0.0;
      for (const VolumeJobsBytes& part : parts) entries += static_cast<double>(part.entries());
      check_memory(entries * (12.0 + 4.0 * (ifs.dim() - 3)),
                   "merging a " + std::to_string(options.resolution) + "^3 point-recursive volume");
    }
    Volume volume = finish_volume_jobs(parts, setup.grid, ifs, setup.quantizer, options.density, kVolumeMassUnit,
                                       setup.threads);
    volume.algorithm = header.algorithm;
    volume.depth = header.depth;
    volume.points = header.points;
    header = std::move(volume);
  }
  if (options.progress && !options.progress(1.0)) throw Cancelled();
  return header;
}

std::string PointRecursiveVolume::draw_jobs(const Ifs& ifs, const VolumeOptions& options, std::uint64_t first,
                                            std::uint64_t last) const {
  PrrJobs run = point_recursive_jobs(ifs, options, first, last, options.progress, false);
  int depth = 0;
  std::uint64_t points = 0;
  for (int d : run.deepest) depth = std::max(depth, d);
  for (std::uint64_t l : run.leaves) points += l;
  return encode_volume_jobs(run.lists, points, depth, options.density, run.setup.threads);
}

}  // namespace ifsforge
