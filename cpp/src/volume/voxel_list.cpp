#include "ifsforge/volume/voxel_list.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "ifsforge/core/error.h"
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

/// What a thread of a slab merge reuses from slab to slab.
struct SlabScratch {
  std::vector<Ref> order, scratch;
  std::vector<std::uint64_t> bits, sums;
  std::vector<std::uint32_t> ranks;
  std::vector<VoxelList> lists;  ///< a loaded slab's lists (finish_volume with a SlabLoader)
};

/// Merges `slabs` slabs on `threads` threads in two passes, so that nothing is built twice:
/// count(s, scratch) gives slab s's voxels, allocate(total) sizes the output, then
/// fill(s, scratch, index) writes slab s's voxels from `index` on (slabs in key order).
template <typename Count, typename Allocate, typename Fill>
void two_pass(std::size_t slabs, int threads, Count&& count, Allocate&& allocate, Fill&& fill) {
  std::vector<SlabScratch> workers(static_cast<std::size_t>(std::max(1, threads)));
  std::vector<std::size_t> at(slabs + 1, 0);
  parallel_jobs(slabs, threads, [&](std::size_t s, int worker) { at[s + 1] = count(s, workers[worker]); });
  for (std::size_t s = 0; s < slabs; ++s) at[s + 1] += at[s];
  allocate(at[slabs]);
  parallel_jobs(slabs, threads, [&](std::size_t s, int worker) { fill(s, workers[worker], at[s]); });
}

/// The sorted lists of jobs or workers cut into a fixed number of x-slabs (slab s holds the
/// keys with i in [s w, (s + 1) w)): the slabs are reduced independently, in parallel, and
/// are disjoint and ascending, so their results only need to be put side by side.
class SlabMerge {
 public:
  /// `most`: the largest number of slabs (1: one sort of everything, for small lists). `width`
  /// (non-zero): slabs of exactly that many rows instead, from a multiple of it (first_slab()).
  explicit SlabMerge(const std::vector<VoxelList>& lists, std::uint64_t most = 64, std::uint64_t width = 0) {
    std::uint64_t first_key = ~std::uint64_t(0), last_key = 0, any = 0;
    channels_ = lists.empty() ? 0 : lists.front().channels;
    points_ = true;
    for (const VoxelList& list : lists)
      if (list.size()) {
        if (sources_.empty()) channels_ = list.channels;
        if (list.channels != channels_) throw InputError("merging voxel lists with different channels");
        sources_.push_back(&list);
        first_key = std::min(first_key, list.keys.front());
        last_key = std::max(last_key, list.keys.back());
        for (std::uint64_t key : list.keys) any |= key;
        points_ = points_ && !list.points.empty();  // extremes only when every list has them
      }
    points_ = points_ && !sources_.empty();
    constexpr std::uint64_t field = (std::uint64_t(1) << VoxelGrid::kKeyBits) - 1;
    bits_j_ = bit_width((any >> VoxelGrid::kKeyBits) & field);
    bits_k_ = bit_width(any & field);
    // The slabs span the rows the keys occupy (one slab of a larger merge starts past row 0).
    first_row_ = sources_.empty() ? 0 : VoxelGrid::coord(first_key)[0];
    if (width) first_row_ -= first_row_ % width;
    const std::uint64_t rows = sources_.empty() ? 0 : VoxelGrid::coord(last_key)[0] + 1 - first_row_;
    if (width) most = (rows + width - 1) / width;
    slabs_ = sources_.empty() ? 0 : static_cast<std::size_t>(std::min<std::uint64_t>(most, rows));
    width_ = width ? width : slabs_ ? (rows + slabs_ - 1) / slabs_ : 1;
    rows_ = rows;
    cuts_.assign(sources_.size(), std::vector<std::size_t>(slabs_ + 1));
    for (std::size_t l = 0; l < sources_.size(); ++l) {
      const auto& keys = sources_[l]->keys;
      for (std::size_t s = 0; s <= slabs_; ++s)
        cuts_[l][s] = static_cast<std::size_t>(std::lower_bound(keys.begin(), keys.end(), start(s)) - keys.begin());
    }
  }
  std::size_t slabs() const { return slabs_; }
  /// @brief The index of slab 0 among slabs of its width counted from row 0.
  std::size_t first_slab() const { return static_cast<std::size_t>(first_row_ / width_); }
  int channels() const { return channels_; }
  bool points() const { return points_; }
  /// @brief The entries of slab s in `order`, sorted by key (compacted: see key_of).
  void sort(std::size_t s, std::vector<Ref>& order, std::vector<Ref>& scratch) const {
    order.clear();
    each_entry(s, [&](std::size_t l, std::size_t i, std::uint64_t c) { order.push_back({c, (std::uint64_t(l) << 32) | i}); });
    if (sources_.size() > 1) radix_sort(order, scratch);
  }
  /// @brief The number of distinct keys in slab s: a sort, or (when a slab's compacted keys
  /// span at most kBitmapBits) one bit per key, set and counted, then cleared (`bits` stays
  /// zero between calls): at 1024^3 a 2 MB bitmap in the core's cache instead of a radix sort.
  std::size_t distinct(std::size_t s, SlabScratch& w) const {
    if (sources_.size() > 1 && bitmap_fits()) {
      std::vector<std::uint64_t>& bits = bitmap(w);
      std::size_t voxels = 0;
      each_entry(s, [&](std::size_t, std::size_t, std::uint64_t c) {
        std::uint64_t& word = bits[c >> 6];
        voxels += (word >> (c & 63) & 1) ^ 1;
        word |= std::uint64_t(1) << (c & 63);
      });
      each_entry(s, [&](std::size_t, std::size_t, std::uint64_t c) { bits[c >> 6] = 0; });
      return voxels;
    }
    sort(s, w.order, w.scratch);
    std::size_t voxels = 0;
    for (std::size_t k = 0; k < w.order.size(); ++k) voxels += k == 0 || w.order[k].key != w.order[k - 1].key;
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

  /// @brief Merges on `threads` threads (see two_pass): write(index, key, hits, mass, sums,
  /// extremes) for every voxel, index in key order.
  template <typename Allocate, typename Write>
  void run(int threads, Allocate&& allocate, Write&& write) const {
    two_pass(
        slabs_, threads, [&](std::size_t s, SlabScratch& w) { return distinct(s, w); },
        allocate, [&](std::size_t s, SlabScratch& w, std::size_t index) { write_slab(s, w, index, write); });
  }
  /// @brief Slab s's voxels through write(index++, ...) from `index` on.
  template <typename Write>
  void write_slab(std::size_t s, SlabScratch& w, std::size_t index, Write&& write) const {
    reduce_slab(s, w, [&](std::uint64_t key, std::uint64_t hits, std::uint64_t mass, const std::uint64_t* sums,
                          const std::uint64_t* extremes) { write(index++, key, hits, mass, sums, extremes); });
  }
  /// @brief reduce() for slab s: by rank on a bitmap where one fits, else after a sort.
  template <typename Visit>
  void reduce_slab(std::size_t s, SlabScratch& w, Visit&& visit) const {
    if (sources_.size() > 1 && bitmap_fits()) return reduce_by_rank(s, w, visit);
    sort(s, w.order, w.scratch);
    reduce(s, w.order, visit);
  }
  /// @brief What sort and reduce give, without sorting: every entry's bit set on a bitmap of
  /// the slab, the bits counted word by word, each entry's sums added at its voxel's rank
  /// (the voxels before it), and the voxels visited in key order from the bitmap, which is
  /// left clear. At 2048^3 a quarter of a merge's time was its radix sorts.
  template <typename Visit>
  void reduce_by_rank(std::size_t s, SlabScratch& w, Visit&& visit) const {
    const std::size_t words = bitmap_words();
    std::vector<std::uint64_t>& bits = bitmap(w);
    if (w.ranks.size() < words) w.ranks.resize(words);
    each_entry(s, [&](std::size_t, std::size_t, std::uint64_t c) { bits[c >> 6] |= std::uint64_t(1) << (c & 63); });
    std::uint32_t voxels = 0;
    for (std::size_t k = 0; k < words; ++k) {
      w.ranks[k] = voxels;
      voxels += static_cast<std::uint32_t>(__builtin_popcountll(bits[k]));
    }
    // Per voxel: hits, mass, the channel sums, then the extremes (minima start high).
    const int nc = channels_, extremes = points_ ? VoxelList::kExtremes : 0;
    const std::size_t stride = 2 + nc + extremes;
    w.sums.assign(voxels * stride, 0);
    for (std::size_t v = 0; v < voxels; ++v)
      for (int e = 0; e < extremes; e += 2) w.sums[v * stride + 2 + nc + e] = ~std::uint64_t(0);
    each_entry(s, [&](std::size_t l, std::size_t i, std::uint64_t c) {
      const VoxelList& list = *sources_[l];
      const std::uint64_t below = bits[c >> 6] & ((std::uint64_t(1) << (c & 63)) - 1);
      std::uint64_t* a = &w.sums[(w.ranks[c >> 6] + __builtin_popcountll(below)) * stride];
      a[0] += list.hits.empty() ? 1 : list.hits[i];
      a[1] += list.mass.empty() ? 0 : list.mass[i];
      for (int ch = 0; ch < nc; ++ch) a[2 + ch] += list.sums[i * nc + ch];
      for (int e = 0; e < extremes; ++e) {
        const std::uint64_t p = list.points[i * VoxelList::kExtremes + e];
        a[2 + nc + e] = e % 2 ? std::max(a[2 + nc + e], p) : std::min(a[2 + nc + e], p);
      }
    });
    std::size_t v = 0;
    for (std::size_t k = 0; k < words; ++k) {
      for (std::uint64_t word = bits[k]; word; word &= word - 1) {
        const std::uint64_t* a = &w.sums[v++ * stride];
        visit(key_of(s, (std::uint64_t(k) << 6) + __builtin_ctzll(word)), a[0], a[1], a + 2,
              extremes ? a + 2 + nc : nullptr);
      }
      bits[k] = 0;
    }
  }

 private:
  bool bitmap_fits() const { return (width_ << (bits_j_ + bits_k_)) <= kBitmapBits; }
  /// Words of a slab's bitmap: one bit per compacted key.
  std::size_t bitmap_words() const { return static_cast<std::size_t>((width_ << (bits_j_ + bits_k_)) / 64 + 1); }
  /// The thread's bitmap, at least bitmap_words() long (zero between uses).
  std::vector<std::uint64_t>& bitmap(SlabScratch& w) const {
    if (w.bits.size() < bitmap_words()) w.bits.assign(bitmap_words(), 0);
    return w.bits;
  }
  /// Calls f(list, index, compacted key) for every entry of slab s, list by list.
  template <typename F>
  void each_entry(std::size_t s, F&& f) const {
    const std::uint64_t base = start(s);
    for (std::size_t l = 0; l < sources_.size(); ++l)
      for (std::size_t i = cuts_[l][s]; i < cuts_[l][s + 1]; ++i) f(l, i, compact(sources_[l]->keys[i] - base));
  }
  std::uint64_t start(std::size_t s) const {
    return VoxelGrid::key(first_row_ + std::min<std::uint64_t>(s * width_, rows_), 0, 0);
  }
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
  std::uint64_t width_ = 1, rows_ = 0, first_row_ = 0;
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

void merge_slabs(const std::vector<VoxelList>& lists, std::uint64_t width, int threads,
                 const std::function<void(std::size_t slab, const VoxelList& merged)>& visit) {
  const SlabMerge merge(lists, 0, width);
  std::vector<SlabScratch> workers(static_cast<std::size_t>(std::max(1, threads)));
  parallel_jobs(merge.slabs(), threads, [&](std::size_t s, int worker) {
    SlabScratch& w = workers[worker];
    w.lists.resize(1);
    VoxelList& out = w.lists[0];
    out.channels = merge.channels();
    out.clear();
    merge.reduce_slab(s, w, [&](std::uint64_t key, std::uint64_t hits, std::uint64_t mass, const std::uint64_t* sums,
                                 const std::uint64_t* extremes) {
      out.push(key, hits, mass, sums);
      if (extremes) out.points.insert(out.points.end(), extremes, extremes + VoxelList::kExtremes);
    });
    if (out.size()) visit(merge.first_slab() + s, out);
  });
}

void sort_and_reduce(VoxelList& list) {
  // Sorted (equal keys side by side), the list merges with itself alone; with no key twice (a
  // hash table's voxels) the sorted list is already what the merge would give.
  std::vector<Ref> order(list.size()), scratch;
  for (std::size_t i = 0; i < list.size(); ++i) order[i] = {list.keys[i], i};
  if (!order.empty()) radix_sort(order, scratch);
  std::vector<VoxelList> sorted(1, VoxelList(list.channels));
  sorted[0].reserve(order.size());
  bool repeated = false;
  for (std::size_t k = 0; k < order.size(); ++k) {
    repeated |= k > 0 && order[k].key == order[k - 1].key;
    sorted[0].push_from(list, order[k].where);
  }
  list = repeated ? merged(SlabMerge(sorted, 1), 1) : std::move(sorted[0]);
}

namespace {

/// Sizes a volume for `total` voxels and writes voxel v from its merged sums: density by
/// `mode` (Measure: mass over `total_mass`), channel means through the quantizer.
struct VolumeWriter {
  Volume& volume;
  const ChannelQuantizer& quantizer;
  VolumeDensity mode;
  double total_mass;
  int channels;
  int threads = 1;  ///< sizing the arrays (between the merge's passes, where nothing else runs)

  void allocate(std::size_t total) const {
    // Faulted in on every core, then each array's zeros written on a core of its own: as one
    // resize after another they were the largest part of a render's time on one core.
    reserve_large(volume.keys, total);
    reserve_large(volume.density, total);
    reserve_large(volume.channels, total * channels);
    const auto size = [&](std::size_t array, int) {
      if (array == 0) volume.keys.resize(total);
      if (array == 1) volume.density.resize(total);
      if (array == 2) volume.channels.resize(total * channels);
    };
    if (threads > 1) return parallel_jobs(3, threads, size);
    for (std::size_t array = 0; array < 3; ++array) size(array, 0);
  }
  void operator()(std::size_t v, std::uint64_t key, std::uint64_t hits, std::uint64_t mass, const std::uint64_t* sums,
                  const std::uint64_t*) const {
    constexpr float kCovered = std::numeric_limits<float>::denorm_min();
    float d = 1.0f;
    if (mode == VolumeDensity::Hits) d = static_cast<float>(hits);
    if (mode == VolumeDensity::Measure) d = std::max(static_cast<float>(static_cast<double>(mass) / total_mass), kCovered);
    volume.keys[v] = key;
    volume.density[v] = d;
    for (int c = 0; c < channels; ++c)
      volume.channels[v * channels + c] = static_cast<float>(quantizer.mean(c, sums[c], hits));
  }
};

}  // namespace

Volume empty_volume(const VoxelGrid& grid, const Ifs& ifs, const ChannelQuantizer& quantizer, VolumeDensity mode) {
  Volume volume;
  volume.grid = grid;
  volume.density_mode = mode;
  const auto& names = ifs.layout().names();
  volume.channel_names.assign(names.begin() + ifs.spatial_dims(), names.end());
  volume.color_model = ifs.layout().color_model();
  volume.channel_lo = quantizer.lo();
  volume.channel_hi = quantizer.hi();
  return volume;
}

Volume finish_volume(std::vector<VoxelList>& lists, const VoxelGrid& grid, const Ifs& ifs,
                     const ChannelQuantizer& quantizer, VolumeDensity mode, double total_mass, int threads) {
  Volume volume = empty_volume(grid, ifs, quantizer, mode);
  const SlabMerge merge(lists);
  const VolumeWriter write{volume, quantizer, mode, total_mass, merge.channels(), threads};
  merge.run(threads, [&](std::size_t total) { write.allocate(total); }, write);
  lists.clear();
  return volume;
}

Volume finish_volume(std::size_t slabs, const SlabLoader& load, const VoxelGrid& grid, const Ifs& ifs,
                     const ChannelQuantizer& quantizer, VolumeDensity mode, double total_mass, int threads) {
  Volume volume = empty_volume(grid, ifs, quantizer, mode);
  const VolumeWriter write{volume, quantizer, mode, total_mass, ifs.dim() - ifs.spatial_dims(), threads};
  // Each loaded slab is one merge of a single slab (its rows alone: a bitmap in cache).
  two_pass(
      slabs, threads,
      [&](std::size_t s, SlabScratch& w) -> std::size_t {
        load(s, w.lists, true);
        const SlabMerge merge(w.lists, 1);
        return merge.slabs() ? merge.distinct(0, w) : 0;
      },
      [&](std::size_t total) { write.allocate(total); },
      [&](std::size_t s, SlabScratch& w, std::size_t index) {
        load(s, w.lists, false);
        const SlabMerge merge(w.lists, 1);
        if (merge.slabs()) merge.write_slab(0, w, index, write);
      });
  return volume;
}

VoxelSpan finish_slabs(std::size_t first, std::size_t last, const SlabLoader& load, const ChannelQuantizer& quantizer,
                       VolumeDensity mode, double total_mass, int channels, Volume& out) {
  thread_local SlabScratch w;  // a thread of the band writer's, band after band
  out.keys.clear();
  out.density.clear();
  out.channels.clear();
  const VolumeWriter write{out, quantizer, mode, total_mass, channels};
  for (std::size_t s = first; s < last; ++s) {
    if (stop_requested()) throw Cancelled();  // a band's merge takes up to a second under load
    load(s, w.lists, false);
    const SlabMerge merge(w.lists, 1);
    if (!merge.slabs()) continue;
    merge.reduce_slab(0, w, [&](std::uint64_t key, std::uint64_t hits, std::uint64_t mass, const std::uint64_t* sums,
                                const std::uint64_t* extremes) {
      const std::size_t v = out.keys.size();
      out.keys.push_back(key);
      out.density.push_back(0.0f);
      out.channels.resize(out.channels.size() + channels);
      write(v, key, hits, mass, sums, extremes);
    });
  }
  return VoxelSpan{out.keys.data(), out.density.data(), out.channels.data(), out.keys.size()};
}

Volume finish_volume(VoxelList&& list, const VoxelGrid& grid, const Ifs& ifs, const ChannelQuantizer& quantizer,
                     VolumeDensity mode, double total_mass, int threads) {
  std::vector<VoxelList> lists;
  lists.push_back(std::move(list));
  return finish_volume(lists, grid, ifs, quantizer, mode, total_mass, threads);
}

}  // namespace ifsforge
