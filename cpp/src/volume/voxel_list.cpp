#include "ifsforge/volume/voxel_list.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "ifsforge/core/parallel.h"

namespace ifsforge {

ChannelQuantizer::ChannelQuantizer(std::vector<double> lo, std::vector<double> hi)
    : lo_(std::move(lo)), hi_(std::move(hi)), scale_(lo_.size(), 0.0) {
  for (std::size_t c = 0; c < lo_.size(); ++c)
    if (hi_[c] > lo_[c]) scale_[c] = kSteps / (hi_[c] - lo_[c]);
}

namespace {

/// Sums the entries `order` of `from` (sorted by key) into `out`, one entry per key.
void reduce_sorted(const std::vector<std::pair<std::uint64_t, std::uint64_t>>& order,
                   const std::vector<const VoxelList*>& sources, VoxelList& out) {
  const int nc = out.channels;
  const bool points = !sources.empty() && !sources.front()->points.empty();
  std::vector<std::uint64_t> sums(nc);
  std::size_t k = 0;
  while (k < order.size()) {
    const std::uint64_t key = order[k].first;
    std::uint64_t hits = 0, mass = 0;
    std::uint64_t extremes[VoxelList::kExtremes];
    for (int e = 0; e < VoxelList::kExtremes; ++e) extremes[e] = e % 2 ? 0 : ~std::uint64_t(0);
    std::fill(sums.begin(), sums.end(), 0);
    for (; k < order.size() && order[k].first == key; ++k) {
      const VoxelList& list = *sources[order[k].second >> 32];
      const std::size_t i = order[k].second & 0xFFFFFFFFu;
      hits += list.hits[i];
      mass += list.mass[i];
      for (int c = 0; c < nc; ++c) sums[c] += list.sums[i * nc + c];
      for (int e = 0; points && e < VoxelList::kExtremes; ++e) {
        const std::uint64_t v = list.points[i * VoxelList::kExtremes + e];
        extremes[e] = e % 2 ? std::max(extremes[e], v) : std::min(extremes[e], v);
      }
    }
    out.push(key, hits, mass, sums.data());
    if (points) out.points.insert(out.points.end(), extremes, extremes + VoxelList::kExtremes);
  }
}

}  // namespace

void sort_and_reduce(VoxelList& list) {
  std::vector<std::pair<std::uint64_t, std::uint64_t>> order(list.size());
  for (std::size_t i = 0; i < list.size(); ++i) order[i] = {list.keys[i], i};
  // Integer sums make the order among equal keys irrelevant.
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  VoxelList out(list.channels);
  reduce_sorted(order, {&list}, out);
  list = std::move(out);
}

VoxelList merge_voxel_lists(std::vector<VoxelList>& lists, int threads) {
  const int nc = lists.empty() ? 0 : lists.front().channels;
  std::vector<const VoxelList*> sources;
  std::uint64_t last_key = 0;
  for (const VoxelList& list : lists)
    if (list.size()) {
      sources.push_back(&list);
      last_key = std::max(last_key, list.keys.back());
    }
  if (sources.size() <= 1) {
    VoxelList out(nc);
    for (VoxelList& list : lists)
      if (list.size()) out = std::move(list);
    lists.clear();
    return out;
  }
  // A fixed number of x-slabs: slab s holds the keys with i in [s w, (s + 1) w).
  const std::uint64_t rows = VoxelGrid::coord(last_key)[0] + 1;
  const std::size_t slabs = static_cast<std::size_t>(std::min<std::uint64_t>(64, rows));
  const std::uint64_t width = (rows + slabs - 1) / slabs;
  auto slab_start = [&](std::size_t s) { return VoxelGrid::key(std::min<std::uint64_t>(s * width, rows), 0, 0); };
  std::vector<std::vector<std::size_t>> cuts(sources.size(), std::vector<std::size_t>(slabs + 1));
  for (std::size_t l = 0; l < sources.size(); ++l) {
    const auto& keys = sources[l]->keys;
    for (std::size_t s = 0; s <= slabs; ++s)
      cuts[l][s] = static_cast<std::size_t>(std::lower_bound(keys.begin(), keys.end(), slab_start(s)) - keys.begin());
  }
  std::vector<VoxelList> parts(slabs, VoxelList(nc));
  parallel_jobs(slabs, threads, [&](std::size_t s, int) {
    std::vector<std::pair<std::uint64_t, std::uint64_t>> order;
    std::size_t total = 0;
    for (std::size_t l = 0; l < sources.size(); ++l) total += cuts[l][s + 1] - cuts[l][s];
    order.reserve(total);
    for (std::size_t l = 0; l < sources.size(); ++l)
      for (std::size_t i = cuts[l][s]; i < cuts[l][s + 1]; ++i)
        order.emplace_back(sources[l]->keys[i], (std::uint64_t(l) << 32) | i);
    std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    reduce_sorted(order, sources, parts[s]);
  });
  lists.clear();
  VoxelList out(nc);
  std::size_t total = 0;
  for (const auto& p : parts) total += p.size();
  out.keys.reserve(total);
  out.hits.reserve(total);
  out.mass.reserve(total);
  out.sums.reserve(total * nc);
  if (!sources.front()->points.empty()) out.points.reserve(total * VoxelList::kExtremes);
  for (auto& p : parts) {
    out.keys.insert(out.keys.end(), p.keys.begin(), p.keys.end());
    out.hits.insert(out.hits.end(), p.hits.begin(), p.hits.end());
    out.mass.insert(out.mass.end(), p.mass.begin(), p.mass.end());
    out.sums.insert(out.sums.end(), p.sums.begin(), p.sums.end());
    out.points.insert(out.points.end(), p.points.begin(), p.points.end());
    p = VoxelList(nc);
  }
  return out;
}

Volume finish_volume(VoxelList&& list, const VoxelGrid& grid, const Ifs& ifs,
                     const ChannelQuantizer& quantizer, VolumeDensity mode, double total_mass) {
  Volume volume;
  volume.grid = grid;
  volume.density_mode = mode;
  const auto& names = ifs.layout().names();
  volume.channel_names.assign(names.begin() + ifs.spatial_dims(), names.end());
  volume.color_model = ifs.layout().color_model();
  volume.channel_lo = quantizer.lo();
  volume.channel_hi = quantizer.hi();
  const std::size_t n = list.size();
  const int nc = list.channels;
  volume.density.resize(n);
  volume.channels.resize(n * nc);
  constexpr float kCovered = std::numeric_limits<float>::denorm_min();
  for (std::size_t v = 0; v < n; ++v) {
    float d = 1.0f;
    if (mode == VolumeDensity::Hits) d = static_cast<float>(list.hits[v]);
    if (mode == VolumeDensity::Measure)
      d = std::max(static_cast<float>(static_cast<double>(list.mass[v]) / total_mass), kCovered);
    volume.density[v] = d;
    for (int c = 0; c < nc; ++c)
      volume.channels[v * nc + c] = static_cast<float>(quantizer.mean(c, list.sums[v * nc + c], list.hits[v]));
  }
  volume.keys = std::move(list.keys);
  list = VoxelList(nc);
  return volume;
}

ProgressCallback progress_range(const ProgressCallback& progress, double from, double to) {
  if (!progress) return nullptr;
  return [progress, from, to](double f) { return progress(from + f * (to - from)); };
}

}  // namespace ifsforge
