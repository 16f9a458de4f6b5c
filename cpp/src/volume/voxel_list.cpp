#include "ifsforge/volume/voxel_list.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {

ChannelQuantizer::ChannelQuantizer(std::vector<double> lo, std::vector<double> hi)
    : lo_(std::move(lo)), hi_(std::move(hi)), scale_(lo_.size(), 0.0) {
  for (std::size_t c = 0; c < lo_.size(); ++c)
    if (hi_[c] > lo_[c]) scale_[c] = kSteps / (hi_[c] - lo_[c]);
}

namespace {

/// An entry of a source list: its key, and which list (high 32 bits) and index (low 32 bits).
struct Ref {
  std::uint64_t key, where;
};

/// Bits needed to hold `v`.
int bit_width(std::uint64_t v) {
  int bits = 0;
  for (; v; v >>= 1) ++bits;
  return bits;
}

/// Sorts refs by key: an LSD radix sort over the bits any key uses, in as few passes of at
/// most 12 bits as they allow. The order among equal keys is left open: their sums, minima
/// and maxima do not depend on it.
void radix_sort(std::vector<Ref>& refs, std::vector<Ref>& scratch) {
  // Below a few thousand entries the bucket counts would cost more than the entries.
  if (refs.size() < 4096) {
    std::sort(refs.begin(), refs.end(), [](const Ref& a, const Ref& b) { return a.key < b.key; });
    return;
  }
  std::uint64_t any = 0;
  for (const Ref& r : refs) any |= r.key;
  const int bits = bit_width(any);
  const int passes = (bits + 11) / 12;
  if (passes == 0) return;
  const int digit = (bits + passes - 1) / passes;
  const std::uint64_t mask = (std::uint64_t(1) << digit) - 1;
  scratch.resize(refs.size());
  std::vector<std::size_t> count(mask + 1);
  for (int shift = 0; shift < bits; shift += digit) {
    std::fill(count.begin(), count.end(), 0);
    for (const Ref& r : refs) ++count[(r.key >> shift) & mask];
    std::size_t sum = 0;
    for (std::size_t& c : count) {
      const std::size_t here = c;
      c = sum;
      sum += here;
    }
    for (const Ref& r : refs) scratch[count[(r.key >> shift) & mask]++] = r;
    refs.swap(scratch);
  }
}

/// The sorted lists of jobs or workers cut into a fixed number of x-slabs (slab s holds the
/// keys with i in [s w, (s + 1) w)): the slabs are reduced independently, in parallel, and
/// are disjoint and ascending, so their results only need to be put side by side.
class SlabMerge {
 public:
  /// `most`: the largest number of slabs (1: one sort of everything, for small lists).
  explicit SlabMerge(const std::vector<VoxelList>& lists, std::uint64_t most = 64) {
    std::uint64_t last_key = 0, any = 0;
    for (const VoxelList& list : lists)
      if (list.size()) {
        sources_.push_back(&list);
        last_key = std::max(last_key, list.keys.back());
        for (std::uint64_t key : list.keys) any |= key;
      }
    constexpr std::uint64_t field = (std::uint64_t(1) << VoxelGrid::kKeyBits) - 1;
    bits_j_ = bit_width((any >> VoxelGrid::kKeyBits) & field);
    bits_k_ = bit_width(any & field);
    channels_ = lists.empty() ? 0 : lists.front().channels;
    points_ = !sources_.empty() && !sources_.front()->points.empty();
    const std::uint64_t rows = VoxelGrid::coord(last_key)[0] + 1;
    slabs_ = sources_.empty() ? 0 : static_cast<std::size_t>(std::min<std::uint64_t>(most, rows));
    width_ = slabs_ ? (rows + slabs_ - 1) / slabs_ : 1;
    rows_ = rows;
    cuts_.assign(sources_.size(), std::vector<std::size_t>(slabs_ + 1));
    for (std::size_t l = 0; l < sources_.size(); ++l) {
      const auto& keys = sources_[l]->keys;
      for (std::size_t s = 0; s <= slabs_; ++s)
        cuts_[l][s] = static_cast<std::size_t>(std::lower_bound(keys.begin(), keys.end(), start(s)) - keys.begin());
    }
  }
  std::size_t slabs() const { return slabs_; }
  int channels() const { return channels_; }
  bool points() const { return points_; }
  /// @brief The entries of slab s in `order`, sorted by key (compacted: see key_of).
  void sort(std::size_t s, std::vector<Ref>& order, std::vector<Ref>& scratch) const {
    order.clear();
    const std::uint64_t base = start(s);
    for (std::size_t l = 0; l < sources_.size(); ++l)
      for (std::size_t i = cuts_[l][s]; i < cuts_[l][s + 1]; ++i)
        order.push_back({compact(sources_[l]->keys[i] - base), (std::uint64_t(l) << 32) | i});
    if (sources_.size() > 1) radix_sort(order, scratch);
  }
  /// @brief The number of distinct keys in slab s: a sort, or (when a slab's compacted keys
  /// span at most kBitmapBits) one bit per key, set and counted, then cleared (`bits` stays
  /// zero between calls): at 1024^3 a 2 MB bitmap in the core's cache instead of a radix sort.
  std::size_t distinct(std::size_t s, std::vector<std::uint64_t>& bits, std::vector<Ref>& order,
                       std::vector<Ref>& scratch) const {
    const std::uint64_t span = width_ << (bits_j_ + bits_k_);
    if (sources_.size() > 1 && span <= kBitmapBits) {
      if (bits.size() < span / 64 + 1) bits.assign(span / 64 + 1, 0);
      const std::uint64_t base = start(s);
      std::size_t voxels = 0;
      for (int clear = 0; clear < 2; ++clear)
        for (std::size_t l = 0; l < sources_.size(); ++l)
          for (std::size_t i = cuts_[l][s]; i < cuts_[l][s + 1]; ++i) {
            const std::uint64_t c = compact(sources_[l]->keys[i] - base);
            std::uint64_t& word = bits[c >> 6];
            if (clear) {
              word = 0;
            } else {
              voxels += (word >> (c & 63) & 1) ^ 1;
              word |= std::uint64_t(1) << (c & 63);
            }
          }
      return voxels;
    }
    sort(s, order, scratch);
    std::size_t voxels = 0;
    for (std::size_t k = 0; k < order.size(); ++k) voxels += k == 0 || order[k].key != order[k - 1].key;
    return voxels;
  }
  /// @brief The voxel key of a compacted key of slab s.
  std::uint64_t key_of(std::size_t s, std::uint64_t compact) const {
    const std::uint64_t k = compact & ((std::uint64_t(1) << bits_k_) - 1);
    const std::uint64_t j = (compact >> bits_k_) & ((std::uint64_t(1) << bits_j_) - 1);
    const std::uint64_t i = compact >> (bits_j_ + bits_k_);
    return start(s) + (i << (2 * VoxelGrid::kKeyBits)) + (j << VoxelGrid::kKeyBits) + k;
  }
  /// @brief Calls visit(key, hits, mass, sums, extremes) for every voxel of slab s (sorted into
  /// `order`) in key order, with the sums of its entries (extremes: merged by min / max, or
  /// nullptr).
  template <typename Visit>
  void reduce(std::size_t s, const std::vector<Ref>& order, Visit&& visit) const {
    const int nc = channels_;
    std::uint64_t sums[kMaxDim];  // more than the channels of any system
    std::uint64_t extremes[VoxelList::kExtremes];
    std::size_t k = 0;
    while (k < order.size()) {
      const std::uint64_t key = order[k].key;
      std::uint64_t hits = 0, mass = 0;
      for (int e = 0; e < VoxelList::kExtremes; ++e) extremes[e] = e % 2 ? 0 : ~std::uint64_t(0);
      std::fill_n(sums, nc, 0);
      for (; k < order.size() && order[k].key == key; ++k) {
        const VoxelList& list = *sources_[order[k].where >> 32];
        const std::size_t i = order[k].where & 0xFFFFFFFFu;
        hits += list.hits.empty() ? 1 : list.hits[i];
        mass += list.mass.empty() ? 0 : list.mass[i];
        for (int c = 0; c < nc; ++c) sums[c] += list.sums[i * nc + c];
        for (int e = 0; points_ && e < VoxelList::kExtremes; ++e) {
          const std::uint64_t v = list.points[i * VoxelList::kExtremes + e];
          extremes[e] = e % 2 ? std::max(extremes[e], v) : std::min(extremes[e], v);
        }
      }
      visit(key_of(s, key), hits, mass, sums, points_ ? extremes : nullptr);
    }
  }

  /// @brief Merges on `threads` threads in two passes, so that nothing is built twice: the
  /// first counts each slab's voxels, `allocate(total)` sizes the output, the second calls
  /// write(index, key, hits, mass, sums, extremes) for every voxel, index in key order.
  template <typename Allocate, typename Write>
  void run(int threads, Allocate&& allocate, Write&& write) const {
    const std::size_t workers = static_cast<std::size_t>(std::max(1, threads));
    std::vector<std::vector<Ref>> orders(workers), scratch(workers);
    std::vector<std::vector<std::uint64_t>> bits(workers);
    std::vector<std::size_t> at(slabs_ + 1, 0);
    parallel_jobs(slabs_, threads, [&](std::size_t s, int worker) {
      at[s + 1] = distinct(s, bits[worker], orders[worker], scratch[worker]);
    });
    for (std::size_t s = 0; s < slabs_; ++s) at[s + 1] += at[s];
    allocate(at[slabs_]);
    parallel_jobs(slabs_, threads, [&](std::size_t s, int worker) {
      std::vector<Ref>& order = orders[worker];
      sort(s, order, scratch[worker]);
      std::size_t index = at[s];
      reduce(s, order, [&](std::uint64_t key, std::uint64_t hits, std::uint64_t mass, const std::uint64_t* sums,
                           const std::uint64_t* extremes) { write(index++, key, hits, mass, sums, extremes); });
    });
  }

 private:
  std::uint64_t start(std::size_t s) const { return VoxelGrid::key(std::min<std::uint64_t>(s * width_, rows_), 0, 0); }
  /// A key relative to its slab's start with the bits of i, j and k side by side (fewer radix
  /// passes, smaller bitmaps).
  std::uint64_t compact(std::uint64_t r) const {
    constexpr std::uint64_t field = (std::uint64_t(1) << VoxelGrid::kKeyBits) - 1;
    return ((r >> (2 * VoxelGrid::kKeyBits)) << (bits_j_ + bits_k_)) | (((r >> VoxelGrid::kKeyBits) & field) << bits_k_) |
           (r & field);
  }
  static constexpr std::uint64_t kBitmapBits = std::uint64_t(1) << 28;  ///< 32 MB per thread at most

  std::vector<const VoxelList*> sources_;
  std::vector<std::vector<std::size_t>> cuts_;
  std::size_t slabs_ = 0;
  std::uint64_t width_ = 1, rows_ = 0;
  int bits_j_ = 0, bits_k_ = 0;
  int channels_ = 0;
  bool points_ = false;
};

/// The sums of the lists `merge` reads, as one sorted list.
VoxelList merged(const SlabMerge& merge, int threads) {
  const int nc = merge.channels();
  VoxelList out(nc);
  merge.run(
      threads,
      [&](std::size_t total) {
        resize_large(out.keys, total);
        resize_large(out.hits, total);
        resize_large(out.mass, total);
        resize_large(out.sums, total * nc);
        if (merge.points()) resize_large(out.points, total * VoxelList::kExtremes);
      },
      [&](std::size_t v, std::uint64_t key, std::uint64_t hits, std::uint64_t mass, const std::uint64_t* sums,
          const std::uint64_t* extremes) {
        out.keys[v] = key;
        out.hits[v] = hits;
        out.mass[v] = mass;
        std::copy(sums, sums + nc, out.sums.begin() + v * nc);
        if (extremes) std::copy(extremes, extremes + VoxelList::kExtremes, out.points.begin() + v * VoxelList::kExtremes);
      });
  return out;
}

}  // namespace

VoxelList merge_voxel_lists(std::vector<VoxelList>& lists, int threads) {
  VoxelList out = merged(SlabMerge(lists), threads);
  lists.clear();
  return out;
}

void sort_and_reduce(VoxelList& list) {
  // Sorted (equal keys side by side), the list merges with itself alone.
  std::vector<Ref> order(list.size()), scratch;
  for (std::size_t i = 0; i < list.size(); ++i) order[i] = {list.keys[i], i};
  if (!order.empty()) radix_sort(order, scratch);
  std::vector<VoxelList> sorted(1, VoxelList(list.channels));
  sorted[0].reserve(order.size());
  for (const Ref& r : order) sorted[0].push_from(list, r.where);
  list = merged(SlabMerge(sorted, 1), 1);
}

Volume finish_volume(std::vector<VoxelList>& lists, const VoxelGrid& grid, const Ifs& ifs,
                     const ChannelQuantizer& quantizer, VolumeDensity mode, double total_mass, int threads) {
  Volume volume;
  volume.grid = grid;
  volume.density_mode = mode;
  const auto& names = ifs.layout().names();
  volume.channel_names.assign(names.begin() + ifs.spatial_dims(), names.end());
  volume.color_model = ifs.layout().color_model();
  volume.channel_lo = quantizer.lo();
  volume.channel_hi = quantizer.hi();
  const SlabMerge merge(lists);
  const int nc = merge.channels();
  constexpr float kCovered = std::numeric_limits<float>::denorm_min();
  merge.run(
      threads,
      [&](std::size_t total) {
        resize_large(volume.keys, total);
        resize_large(volume.density, total);
        resize_large(volume.channels, total * nc);
      },
      [&](std::size_t v, std::uint64_t key, std::uint64_t hits, std::uint64_t mass, const std::uint64_t* sums,
          const std::uint64_t*) {
        float d = 1.0f;
        if (mode == VolumeDensity::Hits) d = static_cast<float>(hits);
        if (mode == VolumeDensity::Measure)
          d = std::max(static_cast<float>(static_cast<double>(mass) / total_mass), kCovered);
        volume.keys[v] = key;
        volume.density[v] = d;
        for (int c = 0; c < nc; ++c) volume.channels[v * nc + c] = static_cast<float>(quantizer.mean(c, sums[c], hits));
      });
  lists.clear();
  return volume;
}

Volume finish_volume(VoxelList&& list, const VoxelGrid& grid, const Ifs& ifs, const ChannelQuantizer& quantizer,
                     VolumeDensity mode, double total_mass, int threads) {
  std::vector<VoxelList> lists;
  lists.push_back(std::move(list));
  return finish_volume(lists, grid, ifs, quantizer, mode, total_mass, threads);
}

}  // namespace ifsforge
