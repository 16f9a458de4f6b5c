#include "vdb_stream.h"

#include <fcntl.h>
#include <unistd.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/GridDescriptor.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <numeric>
#include <ostream>
#include <streambuf>

#include "ifsforge/core/error.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/io/atomic_file.h"
#include "vdb_archive.h"
#include "vdb_file_at.h"
#include "vdb_layout.h"

namespace ifsforge::detail {
namespace {

/// An output stream appending to a buffer: Blosc's blocks go straight into a band's bytes.
class AppendBuffer : public std::streambuf {
 public:
  LargeVector<char>* out = nullptr;

 protected:
  int_type overflow(int_type c) override {
    if (c != traits_type::eof()) out->push_back(static_cast<char>(c));
    return c;
  }
  std::streamsize xsputn(const char* data, std::streamsize n) override {
    out->insert(out->end(), data, data + n);
    return n;
  }
};

/// Voxels whose values are made at once: the next leaves' voxels, up to this many (or one leaf),
/// so that the values' fetches run ahead across leaves.
constexpr std::uint32_t kBatch = 1024;
static_assert(kBatch >= Leaf::SIZE, "a batch holds a leaf");

/// What one thread keeps between bands.
struct BandScratch {
  Volume volume;                          ///< the loader's storage
  std::vector<std::uint32_t> slot;        ///< leaf + 1 of each (y, z) block of the current 8 rows
  std::vector<std::size_t> touched;       ///< the slots to clear at the next 8 rows
  LargeVector<LeafTopology> leaves;       ///< pass 1: the band's leaves
  std::vector<std::uint32_t> start;       ///< pass 2: each leaf's first voxel in by_leaf
  std::vector<std::uint32_t> end;         ///< pass 2: where each leaf's voxels end in by_leaf
  /// Pass 2: the voxels grouped by leaf, each group ascending; sized for the largest band once, and
  /// never cleared (every element is written before it is read).
  ZeroedVector<std::uint32_t> by_leaf;
  float values[kBatch * 3];               ///< a batch of leaves' values
  std::uint16_t halves[kBatch * 3];       ///< the same as halves (openvdb::math::half's bits)
  std::vector<char> chunk;                ///< leaves next to each other in the file, written together
  LargeVector<char> bytes;                ///< Blosc: a band's bytes of one grid
  AppendBuffer append;
  std::ostream blosc{&append};
};

/// Reads a volume's bands (VolumeBandLoader) into leaves of 8^3 voxels.
class BandWriter {
 public:
  BandWriter(const VoxelGrid& grid, std::size_t bands, const VolumeBandLoader& load, int threads)
      : bands_(bands), load_(load), blocks_k_(static_cast<std::size_t>(grid.dims[2]) / 8 + 1),
        blocks_(blocks_k_ * (static_cast<std::size_t>(grid.dims[1]) / 8 + 1)), dims_(grid.dims),
        scratch_(threads) {}

  std::size_t bands() const { return bands_; }
  std::vector<BandScratch>& scratch() { return scratch_; }

  /// Pass 1: band b's leaves (w.leaves, in file order) and the box of its voxels, from its keys
  /// (grouped by 8 rows of x, in any order and repeated within a group: a merge's inputs).
  void topology(std::size_t b, BandScratch& w, openvdb::CoordBBox& box) {
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

  /// Pass 2: band b's voxels (merged: ascending, distinct), grouped by leaf in w.by_leaf (leaf l's
  /// from w.start[l]) for its leaves `leaves` of pass 1 (file order).
  VoxelSpan voxels(std::size_t b, const std::vector<const LeafTopology*>& leaves, BandScratch& w) {
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

 private:
  /// Once per run of keys: inline, its error path apart (called out of line, it was a third of
  /// the plan's time at 2048^3).
  std::array<int, 3> coord(std::uint64_t key, std::size_t b) const {
    const std::array<int, 3> c = VoxelGrid::coord(key);
    if (__builtin_expect(static_cast<std::size_t>(c[0]) / kVolumeBandRows != b || c[0] >= dims_[0] ||
                             c[1] >= dims_[1] || c[2] >= dims_[2], 0))
      outside(c);
    return c;
  }
  [[noreturn]] __attribute__((noinline, cold)) static void outside(const std::array<int, 3>& c) {
    throw InputError("write_vdb: voxel (" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " +
                     std::to_string(c[2]) + ") lies outside its band or the volume's grid");
  }
  static constexpr std::uint64_t kZ = (std::uint64_t(1) << VoxelGrid::kKeyBits) - 1;  ///< a key's z bits
  std::size_t block(const std::array<int, 3>& c) const { return static_cast<std::size_t>(c[1] >> 3) * blocks_k_ + (c[2] >> 3); }
  void prepare(BandScratch& w) const {
    if (w.slot.size() != blocks_) w.slot.assign(blocks_, 0);
  }
  static void clear(BandScratch& w) {
    for (std::size_t t : w.touched) w.slot[t] = 0;
    w.touched.clear();
  }

  std::size_t bands_;
  const VolumeBandLoader& load_;
  std::size_t blocks_k_, blocks_;
  std::array<int, 3> dims_;
  std::vector<BandScratch> scratch_;
};

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

/// One grid's values of `count` voxels of the band (`voxels`: a few leaves' voxels, each leaf's in
/// its order), as they are stored: floats or halves, in w.values or w.halves.
const char* leaf_values(const StreamGrid& g, const Encoding& e, const VoxelSpan& span, const std::uint32_t* voxels,
                        std::uint32_t count, BandScratch& w) {
  if (e.half && g.halves) {
    g.halves(span, voxels, count, w.halves);
    return reinterpret_cast<const char*>(w.halves);
  }
  g.values(span, voxels, count, w.values);
  if (!e.half) return reinterpret_cast<const char*>(w.values);
  for (std::size_t k = 0; k < std::size_t(count) * e.components; ++k)
    w.halves[k] = openvdb::math::half(w.values[k]).bits();
  return reinterpret_cast<const char*>(w.halves);
}

/// Writes one leaf's buffer at `out`, as LeafNode::writeBuffers does with active-mask compression
/// (inactive values are all background) and without Blosc: the mask, the mask-compression byte
/// (0), the active values (halves when saved as half). Returns its size.
std::size_t put_leaf(const LeafTopology& leaf, const char* values, const Encoding& e, char* out) {
  std::memcpy(out, leaf.mask, kLeafMaskBytes);
  out[kLeafMaskBytes] = 0;  // io::NO_MASK_OR_INACTIVE_VALS
  const std::size_t n = leaf.count * e.value_bytes();
  std::memcpy(out + kLeafMaskBytes + 1, values, n);
  return kLeafMaskBytes + 1 + n;
}

/// Appends one leaf's buffer with Blosc: the mask, the mask-compression byte, the values'
/// Blosc block with its size first. Returns the size of the Blosc block (the delayed-load
/// metadata's compressed size).
std::int64_t append_blosc_leaf(const LeafTopology& leaf, const char* values, const Encoding& e, BandScratch& w) {
  LargeVector<char>& out = w.bytes;
  const char* mask = reinterpret_cast<const char*>(leaf.mask);
  out.insert(out.end(), mask, mask + kLeafMaskBytes);
  out.push_back(0);  // io::NO_MASK_OR_INACTIVE_VALS
  const std::size_t before = out.size();
  w.append.out = &out;
  openvdb::io::bloscToStream(w.blosc, values, e.value_bytes(), leaf.count);
  return static_cast<std::int64_t>(out.size() - before);
}

/// A band's bytes of one grid, kept until the Blosc sizes of every band are known.
struct KeptBytes {
  LargeVector<char> bytes;
  std::vector<std::uint32_t> sizes;
  std::vector<std::int64_t> blosc;
};

}  // namespace

std::uint64_t write_vdb_bands(const std::string& path, const VoxelGrid& voxel_grid, const openvdb::MetaMap& meta,
                     const std::vector<StreamGrid>& grids, std::size_t bands, const VolumeBandLoader& load,
                     std::uint32_t compression, int thread_count, const ProgressCallback& progress) {
  AtomicFile out(path);
  const FileAt file(fileno(out.file()), path);
  // The UUID is a hash of the bytes after it, taken as they are written.
  ContentHash hash(kUuidOffset + kUuidLength);
  const HashedWriter writer_of_file(file, hash);
  BackgroundSync flushes(file);
  const int threads = resolve_threads(thread_count);
  BandWriter writer(voxel_grid, bands, load, threads);
  const Layout layout = plan(writer, progress_range(progress, 0.0, 0.2));
  const std::size_t leaves = layout.leaves.size();
  const bool blosc = compression & openvdb::io::COMPRESS_BLOSC;
  std::vector<Encoding> encodings;
  for (const StreamGrid& g : grids) encodings.push_back({g.components, g.grid->saveFloatAsHalf(), blosc});
  std::vector<std::vector<KeptBytes>> kept(blosc ? bands : 0, std::vector<KeptBytes>(grids.size()));
  std::vector<std::uint64_t> buffers(grids.size(), 0);
  // Grids of one value everywhere (a binary density) are their topology: each leaf's values are a
  // leaf's worth of it, and when every grid is one, the bands' voxels are not loaded (nor merged).
  const bool constant =
      std::all_of(grids.begin(), grids.end(), [](const StreamGrid& g) { return g.constant.has_value(); });
  std::vector<std::vector<char>> constants(grids.size());
  for (std::size_t g = 0; g < grids.size(); ++g) {
    if (!grids[g].constant) continue;
    const float value = *grids[g].constant;
    const std::uint16_t bits = openvdb::math::half(value).bits();
    const char* stored =
        encodings[g].half ? reinterpret_cast<const char*>(&bits) : reinterpret_cast<const char*>(&value);
    for (std::size_t k = 0; k < std::size_t(Leaf::SIZE) * grids[g].components; ++k)
      constants[g].insert(constants[g].end(), stored, stored + (encodings[g].half ? 2 : 4));
  }

  // The heads and topologies, once every leaf's size is known; returns where the file ends.
  auto write_heads = [&](const std::vector<std::vector<std::int64_t>>& blosc_sizes,
                         const std::vector<std::uint64_t>& buffer_bytes) {
    const std::string head = file_head(meta, static_cast<std::int32_t>(grids.size()));
    writer_of_file.write(0, head.data(), head.size());
    std::uint64_t at = head.size();
    // Grids of the same tile encoding share their topology's nodes and leaf masks.
    std::map<bool, ZeroedVector<char>> nodes;
    for (std::size_t g = 0; g < grids.size(); ++g) {
      GridHead grid = grid_head(grids[g], layout, compression, blosc_sizes[g]);
      std::string& bytes = grid.bytes;
      const Encoding& e = encodings[g];
      auto tree = nodes.find(e.blosc && !e.half);
      if (tree == nodes.end()) tree = nodes.emplace(e.blosc && !e.half, topology_nodes(layout, e)).first;
      bytes += topology_head(layout, e);
      buffers[g] = at + bytes.size() + tree->second.size();
      // The grid starts after its offsets (at its compression), its leaves after the topology.
      const std::int64_t offsets[3] = {static_cast<std::int64_t>(at + grid.offsets_at + 3 * sizeof(std::int64_t)),
                                       static_cast<std::int64_t>(buffers[g]),
                                       static_cast<std::int64_t>(buffers[g] + buffer_bytes[g])};
      std::memcpy(&bytes[grid.offsets_at], offsets, sizeof offsets);
      writer_of_file.write(at, bytes.data(), bytes.size());
      writer_of_file.write(at + bytes.size(), tree->second.data(), tree->second.size());
      at = buffers[g] + buffer_bytes[g];
    }
    return at;
  };
  // Writes runs of a band's leaves that sit next to each other in the file.
  auto write_runs = [&](const std::vector<std::size_t>& global, const LargeVector<char>& bytes,
                        const std::vector<std::uint32_t>& sizes, auto&& offset_of) {
    for (std::size_t l = 0, from = 0; l < global.size();) {
      std::size_t end = l + 1, size = sizes[l];
      while (end < global.size() && global[end] == global[end - 1] + 1) size += sizes[end++];
      writer_of_file.write(offset_of(global[l]), bytes.data() + from, size);
      from += size;
      l = end;
    }
  };

  std::uint64_t end = 0;
  if (!blosc) {
    std::vector<std::uint64_t> buffer_bytes;
    for (const Encoding& e : encodings)
      buffer_bytes.push_back((kLeafMaskBytes + 1) * std::uint64_t(leaves) + layout.voxels * e.value_bytes());
    end = write_heads(std::vector<std::vector<std::int64_t>>(grids.size()), buffer_bytes);
  }
  // Pass 2: every band's values, leaf by leaf, made where they are written: in pieces of
  // kChunk bytes (held in the cache until the write copies them), or kept until Blosc's sizes
  // are known.
  constexpr std::size_t kChunk = std::size_t(256) << 10;
  std::size_t largest_band = 0;
  for (const std::vector<std::size_t>& band : layout.band_leaves) {
    std::size_t voxels = 0;
    for (std::size_t i : band) voxels += layout.leaves[i].count;
    largest_band = std::max(largest_band, voxels);
  }
  const std::size_t largest_leaf = kLeafMaskBytes + 1 + std::size_t(Leaf::SIZE) * 3 * 4;
  parallel_jobs(bands, threads, [&](std::size_t b, int worker) {
    BandScratch& w = writer.scratch()[worker];
    const std::vector<std::size_t>& global = layout.band_leaves[b];
    std::vector<const LeafTopology*> leaves;
    for (std::size_t i : global) leaves.push_back(&layout.leaves[i]);
    if (!constant && w.by_leaf.capacity() < largest_band) reserve_large(w.by_leaf, largest_band);
    const VoxelSpan span = constant ? VoxelSpan{} : writer.voxels(b, leaves, w);
    std::vector<std::uint32_t> sizes(blosc ? leaves.size() : 0);
    std::vector<std::int64_t> blosc_sizes(blosc ? leaves.size() : 0);
    if (!blosc && w.chunk.size() < kChunk + largest_leaf) w.chunk.resize(kChunk + largest_leaf);
    for (std::size_t g = 0; g < grids.size(); ++g) {
      if (stop_requested()) throw Cancelled();  // a band takes up to a second at 2048^3
      const Encoding& e = encodings[g];
      // Leaf l's values: those of the batch of leaves [batch_first, batch_end) that holds it (their
      // voxels follow one another in by_leaf), made when its first leaf is reached.
      std::size_t batch_first = 0, batch_end = 0;
      const char* batch = nullptr;
      auto values_of = [&](std::size_t l) {
        if (grids[g].constant) return static_cast<const char*>(constants[g].data());
        if (l >= batch_end) {
          batch_first = l;
          batch_end = l + 1;
          while (batch_end < leaves.size() && w.start[batch_end + 1] - w.start[l] <= kBatch) ++batch_end;
          batch = leaf_values(grids[g], e, span, &w.by_leaf[w.start[l]], w.start[batch_end] - w.start[l], w);
        }
        return batch + std::size_t(w.start[l] - w.start[batch_first]) * e.value_bytes();
      };
      if (!blosc) {
        const std::uint64_t value_bytes = e.value_bytes();
        auto offset_of = [&](std::size_t i) {
          return buffers[g] + (kLeafMaskBytes + 1) * std::uint64_t(i) + layout.first_value[i] * value_bytes;
        };
        std::size_t held = 0, first = 0;  // bytes in the chunk, from leaf `first` on
        for (std::size_t l = 0; l < leaves.size(); ++l) {
          if ((l & 1023) == 1023 && stop_requested()) throw Cancelled();
          if (held && (held >= kChunk || global[l] != global[l - 1] + 1)) {
            writer_of_file.write(offset_of(global[first]), w.chunk.data(), held);
            held = 0;
          }
          if (!held) first = l;
          held += put_leaf(*leaves[l], values_of(l), e, w.chunk.data() + held);
        }
        if (held) writer_of_file.write(offset_of(global[first]), w.chunk.data(), held);
        continue;
      }
      // The band's bytes before Blosc, reserved at once (growing by doubling would copy them),
      // with room for a larger band, so that the thread's next bands reuse the buffer.
      std::size_t need = 0;
      for (const LeafTopology* leaf : leaves) need += kLeafMaskBytes + 1 + leaf->count * e.value_bytes();
      w.bytes.clear();
      if (w.bytes.capacity() < need) w.bytes.reserve(need + need / 2);
      for (std::size_t l = 0; l < leaves.size(); ++l) {
        if ((l & 1023) == 1023 && stop_requested()) throw Cancelled();  // Blosc takes a while per leaf
        const std::size_t before = w.bytes.size();
        blosc_sizes[l] = append_blosc_leaf(*leaves[l], values_of(l), e, w);
        sizes[l] = static_cast<std::uint32_t>(w.bytes.size() - before);
      }
      // Kept as they are; the next band's bytes start in a buffer of this one's size.
      const std::size_t size = w.bytes.size();
      kept[b][g] = {std::move(w.bytes), sizes, blosc_sizes};
      w.bytes = LargeVector<char>();
      w.bytes.reserve(size);
    }
    if (!blosc) flushes.written();
  }, progress_range(progress, 0.2, blosc ? 0.7 : 0.85));
  if (blosc) {
    // Every leaf's size in file order, then the heads, then the kept bytes where they belong.
    std::vector<std::vector<std::int64_t>> blosc_sizes(grids.size(), std::vector<std::int64_t>(leaves));
    std::vector<std::vector<std::uint64_t>> offsets(grids.size(), std::vector<std::uint64_t>(leaves + 1, 0));
    std::vector<std::uint64_t> buffer_bytes(grids.size());
    for (std::size_t g = 0; g < grids.size(); ++g) {
      for (std::size_t b = 0; b < bands; ++b)
        for (std::size_t l = 0; l < layout.band_leaves[b].size(); ++l) {
          offsets[g][layout.band_leaves[b][l] + 1] = kept[b][g].sizes[l];
          blosc_sizes[g][layout.band_leaves[b][l]] = kept[b][g].blosc[l];
        }
      std::partial_sum(offsets[g].begin(), offsets[g].end(), offsets[g].begin());
      buffer_bytes[g] = offsets[g].back();
    }
    end = write_heads(blosc_sizes, buffer_bytes);
    parallel_jobs(bands, threads, [&](std::size_t b, int) {
      for (std::size_t g = 0; g < grids.size(); ++g)
        write_runs(layout.band_leaves[b], kept[b][g].bytes, kept[b][g].sizes,
                   [&](std::size_t i) { return buffers[g] + offsets[g][i]; });
      kept[b].clear();
      flushes.written();
    }, progress_range(progress, 0.7, 0.85));
  }
  flushes.finish();
  const std::string uuid = hash.uuid(end);
  file.write(kUuidOffset, uuid.data(), uuid.size());
  file.sync_pieces(end, progress_range(progress, 0.85, 1.0));
  out.commit();
  return layout.voxels;
}

}  // namespace ifsforge::detail
