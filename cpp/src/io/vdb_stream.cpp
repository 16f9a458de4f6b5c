#include "vdb_stream.h"

#include <fcntl.h>
#include <unistd.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/GridDescriptor.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <numeric>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/io/atomic_file.h"
#include "vdb_archive.h"
#include "vdb_layout.h"

namespace ifsforge::detail {
namespace {

/// What one thread keeps between bands.
struct BandScratch {
  Volume volume;                          ///< the loader's storage
  std::vector<std::uint32_t> slot;        ///< leaf + 1 of each (y, z) block of the current 8 rows
  std::vector<std::size_t> touched;       ///< the slots to clear at the next 8 rows
  std::vector<LeafTopology> leaves;       ///< the band's leaves, in file order
  std::vector<std::uint32_t> leaf_of;     ///< each voxel's leaf
  std::vector<std::uint32_t> by_leaf;     ///< the voxels grouped by leaf, each group ascending
  std::vector<float> values;
  std::vector<openvdb::math::half> halves;
  std::string bytes;
  std::ostringstream blosc;
};

class BandWriter {
 public:
  BandWriter(const VoxelGrid& grid, std::size_t bands, const VolumeBandLoader& load, int threads)
      : bands_(bands), load_(load), blocks_k_(static_cast<std::size_t>(grid.dims[2]) / 8 + 1),
        blocks_(blocks_k_ * (static_cast<std::size_t>(grid.dims[1]) / 8 + 1)), dims_(grid.dims),
        scratch_(threads) {}

  std::size_t bands() const { return bands_; }

  /// Band b's leaves in file order (and each voxel's leaf when `voxels`), from its keys.
  VoxelSpan leaves(std::size_t b, bool voxels, BandScratch& w) {
    const VoxelSpan span_ = load_(b, !voxels, w.volume);
    if (w.slot.size() != blocks_) w.slot.assign(blocks_, 0);
    w.leaves.clear();
    w.leaf_of.resize(voxels ? span_.size : 0);
    std::uint64_t slab = ~std::uint64_t(0);
    for (std::size_t v = 0; v < span_.size; ++v) {
      const std::array<int, 3> c = VoxelGrid::coord(span_.keys[v]);
      if (c[0] / kVolumeBandRows != static_cast<int>(b) || c[1] >= dims_[1] || c[2] >= dims_[2] ||
          (v && span_.keys[v] <= span_.keys[v - 1]))
        throw std::logic_error("write_vdb: a band's voxels are not ascending inside it");
      if (static_cast<std::uint64_t>(c[0] >> 3) != slab) {
        for (std::size_t t : w.touched) w.slot[t] = 0;
        w.touched.clear();
        slab = c[0] >> 3;
      }
      const std::size_t block = static_cast<std::size_t>(c[1] >> 3) * blocks_k_ + (c[2] >> 3);
      std::uint32_t& slot = w.slot[block];
      if (!slot) {
        w.leaves.push_back({file_order(c[0], c[1], c[2])});
        slot = static_cast<std::uint32_t>(w.leaves.size());
        w.touched.push_back(block);
      }
      LeafTopology& leaf = w.leaves[slot - 1];
      const int n = (c[0] & 7) << 6 | (c[1] & 7) << 3 | (c[2] & 7);
      leaf.mask[n >> 6] |= std::uint64_t(1) << (n & 63);
      ++leaf.count;
      if (voxels) w.leaf_of[v] = slot - 1;
    }
    for (std::size_t t : w.touched) w.slot[t] = 0;
    w.touched.clear();
    // Into file order; each voxel's leaf follows.
    std::vector<std::uint32_t> rank(w.leaves.size());
    std::iota(rank.begin(), rank.end(), 0u);
    std::sort(rank.begin(), rank.end(), [&](std::uint32_t a, std::uint32_t c) { return w.leaves[a].order < w.leaves[c].order; });
    std::vector<LeafTopology> sorted(w.leaves.size());
    std::vector<std::uint32_t> place(w.leaves.size());
    for (std::size_t i = 0; i < rank.size(); ++i) {
      sorted[i] = w.leaves[rank[i]];
      place[rank[i]] = static_cast<std::uint32_t>(i);
    }
    w.leaves.swap(sorted);
    if (voxels) {
      for (std::uint32_t& l : w.leaf_of) l = place[l];
      // Counting sort by leaf: a leaf's voxels stay ascending, which is its mask's bit order.
      std::vector<std::uint32_t> start(w.leaves.size() + 1, 0);
      for (std::size_t l = 0; l < w.leaves.size(); ++l) start[l + 1] = start[l] + w.leaves[l].count;
      w.by_leaf.resize(span_.size);
      for (std::size_t v = 0; v < span_.size; ++v) w.by_leaf[start[w.leaf_of[v]]++] = static_cast<std::uint32_t>(v);
    }
    return span_;
  }

  std::vector<BandScratch>& scratch() { return scratch_; }

 private:
  std::size_t bands_;
  const VolumeBandLoader& load_;
  std::size_t blocks_k_, blocks_;
  std::array<int, 3> dims_;
  std::vector<BandScratch> scratch_;
};

/// Pass 1: every band's leaves from its keys.
Layout plan(BandWriter& bands, const ProgressCallback& progress) {
  std::vector<std::vector<LeafTopology>> per_band(bands.bands());
  std::vector<openvdb::CoordBBox> boxes(bands.bands());
  parallel_jobs(bands.bands(), static_cast<int>(bands.scratch().size()), [&](std::size_t b, int worker) {
    BandScratch& w = bands.scratch()[worker];
    const VoxelSpan span = bands.leaves(b, false, w);
    per_band[b] = w.leaves;
    for (std::size_t v = 0; v < span.size; ++v) {
      const std::array<int, 3> c = VoxelGrid::coord(span.keys[v]);
      boxes[b].expand(openvdb::Coord(c[0], c[1], c[2]));
    }
  }, progress);
  Layout layout;
  for (std::size_t b = 0; b < per_band.size(); ++b) {
    layout.band_first.push_back(layout.leaves.size());
    layout.leaves.insert(layout.leaves.end(), per_band[b].begin(), per_band[b].end());
    if (!boxes[b].empty()) layout.bbox.expand(boxes[b]);
    std::vector<LeafTopology>().swap(per_band[b]);
  }
  // Bands follow file order unless the grid reaches past 4096 voxels in y or z (several root nodes).
  auto by_order = [](const LeafTopology& a, const LeafTopology& c) { return a.order < c.order; };
  layout.bands_in_order = std::is_sorted(layout.leaves.begin(), layout.leaves.end(), by_order);
  if (!layout.bands_in_order) std::sort(layout.leaves.begin(), layout.leaves.end(), by_order);
  layout.first_value.resize(layout.leaves.size() + 1, 0);
  for (std::size_t i = 0; i < layout.leaves.size(); ++i) {
    layout.orders.push_back(layout.leaves[i].order);
    layout.first_value[i + 1] = layout.first_value[i] + layout.leaves[i].count;
  }
  layout.voxels = layout.first_value.back();
  return layout;
}

std::size_t global_leaf(const Layout& layout, std::size_t band, std::size_t local, std::uint64_t order) {
  if (layout.bands_in_order) return layout.band_first[band] + local;
  return static_cast<std::size_t>(std::lower_bound(layout.orders.begin(), layout.orders.end(), order) -
                                  layout.orders.begin());
}

/// Appends one leaf's buffer, as LeafNode::writeBuffers does with active-mask compression
/// (inactive values are all background): the mask, the mask-compression byte (0), the active
/// values (halves when saved as half; Blosc-compressed with their size first when asked for).
/// Returns the size of the Blosc block (the delayed-load metadata's compressed size).
std::int64_t append_leaf(const LeafTopology& leaf, const std::uint32_t* voxels, const float* values,
                         const Encoding& e, BandScratch& w) {
  std::string& out = w.bytes;
  out.append(reinterpret_cast<const char*>(leaf.mask), kLeafMaskBytes);
  out.push_back(0);  // io::NO_MASK_OR_INACTIVE_VALS
  const std::size_t n = std::size_t(leaf.count) * e.components;
  const char* data = nullptr;
  if (e.half) {
    w.halves.resize(n);
    for (std::size_t i = 0, k = 0; i < leaf.count; ++i)
      for (int c = 0; c < e.components; ++c) w.halves[k++] = openvdb::math::half(values[std::size_t(voxels[i]) * e.components + c]);
    data = reinterpret_cast<const char*>(w.halves.data());
  } else {
    const std::size_t at = out.size();
    if (!e.blosc) {
      out.resize(at + n * 4);
      for (std::size_t i = 0; i < leaf.count; ++i)
        std::memcpy(&out[at + i * e.components * 4], &values[std::size_t(voxels[i]) * e.components], e.components * 4);
      return 0;
    }
    w.values.resize(n);
    for (std::size_t i = 0; i < leaf.count; ++i)
      std::memcpy(&w.values[i * e.components], &values[std::size_t(voxels[i]) * e.components], e.components * 4);
    data = reinterpret_cast<const char*>(w.values.data());
  }
  if (!e.blosc) {
    out.append(data, n * 2);
    return 0;
  }
  w.blosc.str(std::string());
  openvdb::io::bloscToStream(w.blosc, data, e.value_bytes() / e.components * e.components, leaf.count);
  const std::string block = w.blosc.str();
  out += block;
  return static_cast<std::int64_t>(block.size());
}

/// Writes at offsets of one open file, reporting failures as FileError naming the target.
class FileAt {
 public:
  FileAt(int fd, std::string shown) : fd_(fd), shown_(std::move(shown)) {}
  void write(std::uint64_t offset, const char* data, std::size_t size) const {
    while (size > 0) {
      const ssize_t n = ::pwrite(fd_, data, size, static_cast<off_t>(offset));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) throw FileError("cannot write '" + shown_ + "': " + (n < 0 ? std::strerror(errno) : "the disk refused the data (full?)"));
      data += n;
      size -= static_cast<std::size_t>(n);
      offset += static_cast<std::uint64_t>(n);
    }
  }
  int fd() const { return fd_; }
  const std::string& shown() const { return shown_; }

 private:
  int fd_;
  std::string shown_;
};

/// A band's bytes of one grid, kept until the Blosc sizes of every band are known.
struct KeptBytes {
  std::string bytes;
  std::vector<std::uint32_t> sizes;
  std::vector<std::int64_t> blosc;
};

/// A content hash as a UUID (8-4-4-4-12 hex) of the file's bytes after the UUID: blocks hashed
/// in parallel eight bytes at a time, then the blocks' hashes in order.
std::string content_uuid(const std::string& written, const FileAt& file, std::uint64_t begin, std::uint64_t end) {
  struct Reader {
    int fd;
    ~Reader() { if (fd >= 0) ::close(fd); }
  } reader{::open(written.c_str(), O_RDONLY)};
  if (reader.fd < 0) throw FileError("cannot write '" + file.shown() + "': cannot read it back: " + std::strerror(errno));
  constexpr std::uint64_t kBlock = 4u << 20, kPrime = 0x100000001b3ull;
  const std::size_t blocks = static_cast<std::size_t>((end - begin + kBlock - 1) / kBlock);
  std::vector<std::array<std::uint64_t, 2>> hashes(blocks);
  std::vector<std::vector<char>> buffers(resolve_threads(0), std::vector<char>(kBlock));
  parallel_jobs(blocks, static_cast<int>(buffers.size()), [&](std::size_t k, int worker) {
    char* data = buffers[worker].data();
    const std::uint64_t at = begin + k * kBlock, size = std::min(kBlock, end - at);
    for (std::uint64_t done = 0; done < size;) {
      const ssize_t n = ::pread(reader.fd, data + done, size - done, static_cast<off_t>(at + done));
      if (n <= 0 && !(n < 0 && errno == EINTR)) throw FileError("cannot write '" + file.shown() + "': cannot read it back");
      if (n > 0) done += static_cast<std::uint64_t>(n);
    }
    std::uint64_t a = 0xcbf29ce484222325ull, b = 0x84222325cbf29ce4ull, word = 0;
    std::size_t i = 0;
    for (; i + 8 <= size; i += 8) {
      std::memcpy(&word, data + i, 8);
      a = (a ^ word) * kPrime;
      b = (b ^ (word >> 29 | word << 35)) * kPrime;
    }
    for (; i < size; ++i) a = (a ^ static_cast<unsigned char>(data[i])) * kPrime;
    hashes[k] = {a, b ^ size};
  });
  std::uint64_t a = 0xcbf29ce484222325ull, b = 0x9e3779b97f4a7c15ull;
  for (const auto& h : hashes) {
    a = (a ^ h[0]) * kPrime;
    b = (b ^ h[1]) * kPrime;
  }
  char text[37];
  std::snprintf(text, sizeof text, "%08x-%04x-%04x-%04x-%012llx", unsigned(a >> 32), unsigned((a >> 16) & 0xFFFF),
                unsigned(a & 0xFFFF), unsigned(b >> 48), static_cast<unsigned long long>(b & 0xFFFFFFFFFFFFull));
  return text;
}

}  // namespace

std::uint64_t write_vdb_bands(const std::string& path, const VoxelGrid& voxel_grid, const openvdb::MetaMap& meta,
                     const std::vector<StreamGrid>& grids, std::size_t bands, const VolumeBandLoader& load,
                     std::uint32_t compression, const ProgressCallback& progress) {
  AtomicFile out(path);
  const FileAt file(fileno(out.file()), path);
  const int threads = resolve_threads(0);
  BandWriter writer(voxel_grid, bands, load, threads);
  const Layout layout = plan(writer, progress_range(progress, 0.0, 0.2));
  const std::size_t leaves = layout.leaves.size();
  const bool blosc = compression & openvdb::io::COMPRESS_BLOSC;
  std::vector<Encoding> encodings;
  for (const StreamGrid& g : grids) encodings.push_back({g.components, g.grid->saveFloatAsHalf(), blosc});
  std::vector<std::vector<KeptBytes>> kept(blosc ? bands : 0, std::vector<KeptBytes>(grids.size()));
  std::vector<std::uint64_t> buffers(grids.size(), 0);

  // The heads and topologies, once every leaf's size is known; returns where the file ends.
  auto write_heads = [&](const std::vector<std::vector<std::int64_t>>& blosc_sizes,
                         const std::vector<std::uint64_t>& buffer_bytes) {
    const std::string head = file_head(meta, static_cast<std::int32_t>(grids.size()));
    file.write(0, head.data(), head.size());
    std::uint64_t at = head.size();
    for (std::size_t g = 0; g < grids.size(); ++g) {
      std::string bytes = grid_head(grids[g], layout, compression, blosc_sizes[g]);
      const std::size_t positions = descriptor_bytes(grids[g]);
      bytes += topology(layout, encodings[g]);
      buffers[g] = at + bytes.size();
      const std::int64_t offsets[3] = {static_cast<std::int64_t>(at + positions + 24),
                                       static_cast<std::int64_t>(buffers[g]),
                                       static_cast<std::int64_t>(buffers[g] + buffer_bytes[g])};
      std::memcpy(&bytes[positions], offsets, sizeof offsets);
      file.write(at, bytes.data(), bytes.size());
      at = buffers[g] + buffer_bytes[g];
    }
    return at;
  };
  // Writes runs of a band's leaves that sit next to each other in the file.
  auto write_runs = [&](const std::vector<std::size_t>& global, const std::string& bytes,
                        const std::vector<std::uint32_t>& sizes, auto&& offset_of) {
    for (std::size_t l = 0, from = 0; l < global.size();) {
      std::size_t end = l + 1, size = sizes[l];
      while (end < global.size() && global[end] == global[end - 1] + 1) size += sizes[end++];
      file.write(offset_of(global[l]), bytes.data() + from, size);
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
  // Pass 2: every band's values, leaf by leaf, written in place (or kept until Blosc's sizes are known).
  std::vector<std::vector<float>> band_values(threads);
  std::vector<std::vector<std::size_t>> band_globals(bands);
  parallel_jobs(bands, threads, [&](std::size_t b, int worker) {
    BandScratch& w = writer.scratch()[worker];
    const VoxelSpan span = writer.leaves(b, true, w);
    std::vector<std::size_t>& global = band_globals[b];
    global.resize(w.leaves.size());
    for (std::size_t l = 0; l < global.size(); ++l) global[l] = global_leaf(layout, b, l, w.leaves[l].order);
    std::vector<std::uint32_t> sizes(w.leaves.size());
    std::vector<std::int64_t> blosc_sizes(blosc ? w.leaves.size() : 0);
    for (std::size_t g = 0; g < grids.size(); ++g) {
      if (stop_requested()) throw Cancelled();  // a band takes up to a second at 2048^3
      std::vector<float>& values = band_values[worker];
      values.resize(span.size * grids[g].components);
      grids[g].values(span, values.data());
      w.bytes.clear();
      for (std::size_t l = 0, first = 0; l < w.leaves.size(); first += w.leaves[l++].count) {
        const std::size_t before = w.bytes.size();
        const std::int64_t block = append_leaf(w.leaves[l], &w.by_leaf[first], values.data(), encodings[g], w);
        sizes[l] = static_cast<std::uint32_t>(w.bytes.size() - before);
        if (blosc) blosc_sizes[l] = block;
      }
      if (blosc) {
        kept[b][g] = {w.bytes, sizes, blosc_sizes};
        continue;
      }
      const std::uint64_t value_bytes = encodings[g].value_bytes();
      write_runs(global, w.bytes, sizes, [&](std::size_t i) {
        return buffers[g] + (kLeafMaskBytes + 1) * std::uint64_t(i) + layout.first_value[i] * value_bytes;
      });
    }
  }, progress_range(progress, 0.2, blosc ? 0.9 : 1.0));
  if (blosc) {
    // Every leaf's size in file order, then the heads, then the kept bytes where they belong.
    std::vector<std::vector<std::int64_t>> blosc_sizes(grids.size(), std::vector<std::int64_t>(leaves));
    std::vector<std::vector<std::uint64_t>> offsets(grids.size(), std::vector<std::uint64_t>(leaves + 1, 0));
    std::vector<std::uint64_t> buffer_bytes(grids.size());
    for (std::size_t g = 0; g < grids.size(); ++g) {
      for (std::size_t b = 0; b < bands; ++b)
        for (std::size_t l = 0; l < band_globals[b].size(); ++l) {
          offsets[g][band_globals[b][l] + 1] = kept[b][g].sizes[l];
          blosc_sizes[g][band_globals[b][l]] = kept[b][g].blosc[l];
        }
      std::partial_sum(offsets[g].begin(), offsets[g].end(), offsets[g].begin());
      buffer_bytes[g] = offsets[g].back();
    }
    end = write_heads(blosc_sizes, buffer_bytes);
    parallel_jobs(bands, threads, [&](std::size_t b, int) {
      for (std::size_t g = 0; g < grids.size(); ++g)
        write_runs(band_globals[b], kept[b][g].bytes, kept[b][g].sizes,
                   [&](std::size_t i) { return buffers[g] + offsets[g][i]; });
      kept[b].clear();
    }, progress_range(progress, 0.9, 1.0));
  }
  const std::string uuid = content_uuid(out.temporary_path(), file, 57, end);
  file.write(21, uuid.data(), uuid.size());
  out.commit();
  return layout.voxels;
}

}  // namespace ifsforge::detail
