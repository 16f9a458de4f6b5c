#include "vdb_bands.h"

#include <algorithm>
#include <string>

#include "ifsforge/core/parallel.h"

namespace ifsforge::detail {

void BandWriter::topology(std::size_t b, BandScratch& w, openvdb::CoordBBox& box) {
  const VoxelSpan span = load_(b, true, w.volume);
  prepare(w);
  w.leaves.clear();
  std::uint32_t seen = 0;  // the groups of 8 rows met so far (16 per band)
  int group = -1;
  // Keys of one run (the same x, y and z >> 3) set bits of one word of one leaf's mask: they
  // are gathered in `bits`, and the leaf is looked up once per run.
  std::uint64_t run = ~std::uint64_t(0), bits = 0;
  std::size_t leaf = 0, word = 0;
  int base = 0;
  for (std::size_t v = 0; v < span.size; ++v) {
    if ((v & 0xFFFFF) == 0xFFFFF && stop_requested()) throw Cancelled();  // a band holds ~10^7 keys
    const std::uint64_t key = span.keys[v];
    if (key >> 3 != run) {
      if (bits) w.leaves[leaf].mask[word] |= bits;
      bits = 0;
      run = key >> 3;
      const std::array<int, 3> c = coord(key & ~std::uint64_t(7), b);
      if (c[0] >> 3 != group) {
        group = c[0] >> 3;
        const std::uint32_t bit = std::uint32_t(1) << (group & 15);
        if (seen & bit) throw std::logic_error("write_vdb: a band's keys are not grouped by 8 rows");
        seen |= bit;
        clear(w);
      }
      std::uint32_t& slot = w.slot[block(c)];
      if (!slot) {
        w.leaves.push_back({file_order(c[0], c[1], c[2])});
        slot = static_cast<std::uint32_t>(w.leaves.size());
        w.touched.push_back(block(c));
      }
      leaf = slot - 1;
      word = static_cast<std::size_t>(c[0] & 7);
      base = (c[1] & 7) << 3;
    }
    if (static_cast<int>(key & kZ) >= dims_[2]) coord(key, b);  // throws: outside the grid
    bits |= std::uint64_t(1) << (base | static_cast<int>(key & 7));
  }
  if (bits) w.leaves[leaf].mask[word] |= bits;
  clear(w);
  for (LeafTopology& leaf : w.leaves) {
    // The leaf's voxels' box, from its mask: word x holds bits y << 3 | z.
    std::uint64_t any = 0;
    int x0 = 8, x1 = -1;
    for (int x = 0; x < 8; ++x) {
      leaf.count += static_cast<std::uint32_t>(__builtin_popcountll(leaf.mask[x]));
      any |= leaf.mask[x];
      if (leaf.mask[x]) x0 = std::min(x0, x), x1 = x;
    }
    std::uint64_t zs = 0;
    for (int y = 0; y < 8; ++y) zs |= any >> (8 * y) & 0xFF;
    const openvdb::Coord o = leaf_origin(leaf.order);
    box.expand(openvdb::CoordBBox(o.x() + x0, o.y() + __builtin_ctzll(any) / 8, o.z() + __builtin_ctzll(zs),
                                  o.x() + x1, o.y() + (63 - __builtin_clzll(any)) / 8, o.z() + 63 - __builtin_clzll(zs)));
  }
  std::sort(w.leaves.begin(), w.leaves.end(), [](const LeafTopology& a, const LeafTopology& c) { return a.order < c.order; });
}

VoxelSpan BandWriter::voxels(std::size_t b, const std::vector<const LeafTopology*>& leaves, BandScratch& w) {
  const VoxelSpan span = load_(b, false, w.volume);
  prepare(w);
  // The leaves of each group of 8 rows, to put in the slots when its voxels come.
  std::vector<std::vector<std::uint32_t>> groups(kVolumeBandRows / 8);
  w.start.assign(leaves.size() + 1, 0);
  for (std::size_t l = 0; l < leaves.size(); ++l) {
    groups[leaf_origin(leaves[l]->order).x() >> 3 & 15].push_back(static_cast<std::uint32_t>(l));
    w.start[l + 1] = w.start[l] + leaves[l]->count;
  }
  if (w.start.back() != span.size) throw std::logic_error("write_vdb: a band's voxels are not its keys");
  w.end.assign(w.start.begin() + 1, w.start.end());
  w.by_leaf.resize(span.size);
  int group = -1;
  std::uint64_t run = ~std::uint64_t(0);  // as in topology(): a run's leaf is looked up once
  std::uint32_t* next = nullptr;
  std::uint32_t end = 0;
  for (std::size_t v = 0; v < span.size; ++v) {
    const std::uint64_t key = span.keys[v];
    if (v && key <= span.keys[v - 1]) throw std::logic_error("write_vdb: a band's voxels are not ascending");
    if (key >> 3 != run) {
      run = key >> 3;
      const std::array<int, 3> c = coord(key & ~std::uint64_t(7), b);
      if (c[0] >> 3 != group) {
        clear(w);
        group = c[0] >> 3;
        for (std::uint32_t l : groups[group & 15]) {
          const openvdb::Coord o = leaf_origin(leaves[l]->order);
          const std::size_t k = block({o.x(), o.y(), o.z()});
          w.slot[k] = l + 1;
          w.touched.push_back(k);
        }
      }
      const std::uint32_t slot = w.slot[block(c)];
      if (!slot) throw std::logic_error("write_vdb: a band's voxels are not its keys");
      next = &w.start[slot - 1];
      end = w.end[slot - 1];
    }
    if (static_cast<int>(key & kZ) >= dims_[2]) coord(key, b);  // throws: outside the grid
    if (*next == end) throw std::logic_error("write_vdb: a band's voxels are not its keys");
    w.by_leaf[(*next)++] = static_cast<std::uint32_t>(v);
  }
  clear(w);
  // start[l] now ends leaf l: back to its beginning (each leaf's count was checked by the sum).
  for (std::size_t l = leaves.size(); l-- > 0;) w.start[l + 1] = w.start[l];
  w.start[0] = 0;
  return span;
}

/// Pass 1: every band's leaves from its keys, in file order, and which are whose.
Layout plan(BandWriter& bands, const ProgressCallback& progress) {
  std::vector<LargeVector<LeafTopology>> per_band(bands.bands());
  std::vector<openvdb::CoordBBox> boxes(bands.bands());
  parallel_jobs(bands.bands(), static_cast<int>(bands.scratch().size()), [&](std::size_t b, int worker) {
    BandScratch& w = bands.scratch()[worker];
    bands.topology(b, w, boxes[b]);
    per_band[b] = std::move(w.leaves);
    w.leaves = {};
    w.leaves.reserve(per_band[b].size());  // the next band's, about as many
  }, progress);
  Layout layout;
  std::size_t total = 0;
  for (const auto& leaves : per_band) total += leaves.size();
  layout.leaves.reserve(total);
  layout.orders.reserve(total);
  for (std::size_t b = 0; b < per_band.size(); ++b) {
    layout.leaves.insert(layout.leaves.end(), per_band[b].begin(), per_band[b].end());
    if (!boxes[b].empty()) layout.bbox.expand(boxes[b]);
  }
  // Bands follow file order unless the grid reaches past 4096 voxels in y or z (several root nodes).
  auto by_order = [](const LeafTopology& a, const LeafTopology& c) { return a.order < c.order; };
  const bool in_bands = std::is_sorted(layout.leaves.begin(), layout.leaves.end(), by_order);
  if (!in_bands) std::sort(layout.leaves.begin(), layout.leaves.end(), by_order);
  layout.first_value.resize(layout.leaves.size() + 1, 0);
  for (std::size_t i = 0; i < layout.leaves.size(); ++i) {
    layout.orders.push_back(layout.leaves[i].order);
    layout.first_value[i + 1] = layout.first_value[i] + layout.leaves[i].count;
  }
  layout.voxels = layout.first_value.back();
  // Band b's leaves: the next ones in file order, or found by search after the sort.
  layout.band_leaves.resize(per_band.size());
  for (std::size_t b = 0, next = 0; b < per_band.size(); ++b) {
    layout.band_leaves[b].reserve(per_band[b].size());
    for (const LeafTopology& leaf : per_band[b])
      layout.band_leaves[b].push_back(in_bands ? next++ : static_cast<std::size_t>(
          std::lower_bound(layout.orders.begin(), layout.orders.end(), leaf.order) - layout.orders.begin()));
    LargeVector<LeafTopology>().swap(per_band[b]);
  }
  return layout;
}

}  // namespace ifsforge::detail
