#include "ifsforge/volume/deterministic_iteration_volume.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "voxel_table.h"

namespace ifsforge {
namespace {

constexpr int kMaxLevels = 100;  // Barnsley's suggestion for the screen-rewriting DIA
constexpr std::size_t kJobs = 256;
constexpr double kSteps = 2097152.0;  // 2^21 steps per voxel side for a voxel's point

/// A point of voxel `v` from fractions packed with axis `first` most significant.
void unpack(const VoxelGrid& grid, const std::array<int, 3>& v, std::uint64_t packed, int first, double* out) {
  const std::uint64_t q[3] = {packed >> 42, (packed >> 21) & 0x1FFFFF, packed & 0x1FFFFF};
  for (int k = 0; k < 3; ++k) {
    const int a = (first + k) % 3;
    out[a] = grid.origin[a] + (v[a] + (q[k] + 0.5) / kSteps) * grid.voxel_size;
  }
}

/// The fractions of continuous voxel coordinates `u` inside their voxel, packed for every
/// slot of VoxelList::points: slots 2a and 2a + 1 with axis a most significant.
void pack(const double* u, std::uint64_t* slots) {
  std::uint64_t q[3];
  for (int a = 0; a < 3; ++a)
    q[a] = static_cast<std::uint64_t>(std::clamp((u[a] - std::floor(u[a])) * kSteps, 0.0, kSteps - 1.0));
  for (int a = 0; a < 3; ++a)
    slots[2 * a] = slots[2 * a + 1] = (q[a] << 42) | (q[(a + 1) % 3] << 21) | q[(a + 2) % 3];
}

}  // namespace

Capabilities DeterministicIterationVolume::capabilities() const {
  // The Markov operator on voxel sets: one set for all maps, so no transitions.
  using C = Capabilities;
  return {C::AverageContractive | C::Overlapping | C::Space};
}

Volume DeterministicIterationVolume::draw(const Ifs& ifs, const VolumeOptions& options) const {
  if (options.distribute) run_jobs(ifs, options, 0, 0);  // InputError: no independent jobs
  const VolumeSetup setup = prepare_volume(ifs, options);
  const VoxelGrid& grid = setup.grid;
  const ChannelQuantizer& quantizer = setup.quantizer;
  const int channels = ifs.dim() - 3;
  const std::size_t maps = ifs.size();
  const double cells = grid.cells();
  // The first level reads every voxel of the grid and writes about sum |det| of them per map.
  double jacobian = 0.0;
  for (const auto& m : ifs.maps()) jacobian += std::min(1.0, std::abs(m.determinant(3)));
  const double entry = VoxelList::entry_bytes(channels) + 8.0;
  check_memory(cells * std::max(1.0, jacobian) * 2.0 * entry +
                   cells / kJobs * maps * VoxelTable::bytes_per_voxel(channels, true) * setup.threads,
               "deterministic iteration (volume rewriting) of a " + std::to_string(grid.dims[0]) + "x" +
                   std::to_string(grid.dims[1]) + "x" + std::to_string(grid.dims[2]) + " grid");

  // Eq. 49: the initial image is the whole grid with a uniform measure, each voxel holding its
  // centre and the middle of the channels' range. It is never stored: level 1 enumerates it.
  const std::uint64_t uniform = static_cast<std::uint64_t>(kVolumeMassUnit / cells);
  const double half_voxel[3] = {0.5, 0.5, 0.5};
  std::uint64_t middle_points[VoxelList::kExtremes];
  pack(half_voxel, middle_points);
  std::vector<std::uint64_t> middle(channels);
  for (int c = 0; c < channels; ++c) middle[c] = quantizer.quantize(c, setup.center[3 + c]);
  VoxelList current(channels);
  const int levels = options.depth > 0 ? options.depth : kMaxLevels;
  const double inverse = 1.0 / grid.voxel_size;
  int level = 0;
  std::uint64_t sources_mapped = 0;
  std::vector<VoxelTable> tables(setup.threads, VoxelTable(channels, true));
  for (; level < levels; ++level) {
    const bool first = level == 0;
    const std::uint64_t sources = first ? static_cast<std::uint64_t>(cells) : current.size();
    if (sources == 0) break;
    std::vector<VoxelList> lists(kJobs, VoxelList(channels));
    // Levels until occupancy settles are not known in advance: each gets a share of what is left.
    const double from = 1.0 - std::pow(0.8, level), to = 1.0 - std::pow(0.8, level + 1);
    parallel_jobs(kJobs, setup.threads, [&](std::size_t job, int worker) {
      const std::uint64_t begin = sources * job / kJobs, end = sources * (job + 1) / kJobs;
      VoxelTable& out = tables[worker];
      Point p{}, q{};
      std::uint64_t packed[VoxelList::kExtremes];
      std::vector<std::uint64_t> values(channels);
      for (std::uint64_t s = begin; s < end; ++s) {
        std::uint64_t key, mass, hits;
        const std::uint64_t *sums, *points;
        if (first) {
          const std::uint64_t k = s % grid.dims[2], j = (s / grid.dims[2]) % grid.dims[1], i = s / grid.dims[2] / grid.dims[1];
          key = VoxelGrid::key(i, j, k);
          mass = uniform;
          sums = middle.data();
          hits = 1;
          points = middle_points;
        } else {
          key = current.keys[s];
          mass = current.mass[s];
          sums = current.sums.data() + s * channels;  // empty without channels
          hits = current.hits[s];
          points = &current.points[s * VoxelList::kExtremes];
        }
        for (int c = 0; c < channels; ++c) p[3 + c] = quantizer.mean(c, sums[c], hits);
        const auto v = VoxelGrid::coord(key);
        // The voxel's extreme points, each once; each carries the voxel's channels, its mass
        // goes with the first.
        std::array<double, 3> seen[VoxelList::kExtremes];
        int distinct = 0;
        for (int e = 0; e < VoxelList::kExtremes; ++e) {
          unpack(grid, v, points[e], e / 2, p.data());
          const std::array<double, 3> here{p[0], p[1], p[2]};
          if (std::find(seen, seen + distinct, here) != seen + distinct) continue;
          seen[distinct++] = here;
        }
        for (int e = 0; e < distinct; ++e) {
          std::copy(seen[e].begin(), seen[e].end(), p.begin());
          for (std::size_t i = 0; i < maps; ++i) {
            ifs.map(i).apply(p.data(), q.data());
            double u[3];
            bool inside = true;
            for (int a = 0; a < 3; ++a) {
              u[a] = (q[a] - grid.origin[a]) * inverse;
              inside = inside && u[a] >= 0.0 && u[a] < grid.dims[a];
            }
            if (!inside) continue;
            for (int c = 0; c < channels; ++c) values[c] = quantizer.quantize(c, q[3 + c]);
            const auto m = e ? 0 : static_cast<std::uint64_t>(static_cast<double>(mass) * ifs.probabilities()[i] + 0.5);
            pack(u, packed);
            out.add(VoxelGrid::key(static_cast<std::uint64_t>(u[0]), static_cast<std::uint64_t>(u[1]),
                                   static_cast<std::uint64_t>(u[2])),
                    1, m, values.data(), packed);
          }
        }
      }
      lists[job] = out.take();
    }, progress_range(options.progress, from, to));
    sources_mapped += sources * maps;
    VoxelList next = merge_voxel_lists(lists, setup.threads);
    // Occupancy stops changing: the occupied voxels reach the stationary state of Eq. 51 on
    // the grid, where they only flicker by a few voxels out of thousands.
    const double change = std::abs(static_cast<double>(next.size()) - static_cast<double>(current.size()));
    const bool settled = !first && change <= 0.001 * static_cast<double>(next.size());
    current = std::move(next);
    if (settled && options.depth <= 0) {
      ++level;
      break;
    }
  }
  current.points.clear();
  Volume volume = finish_volume(std::move(current), grid, ifs, quantizer, options.density, kVolumeMassUnit,
                                setup.threads);
  volume.algorithm = name();
  volume.depth = level;
  volume.points = sources_mapped;
  if (options.progress && !options.progress(1.0)) throw Cancelled();
  return volume;
}

}  // namespace ifsforge
