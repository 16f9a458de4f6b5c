#include "vdb_stream.h"

#include <fcntl.h>
#include <unistd.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/GridDescriptor.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/io/atomic_file.h"
#include "vdb_archive.h"
#include "vdb_bands.h"
#include "vdb_file_at.h"
#include "vdb_layout.h"

namespace ifsforge::detail {
namespace {

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

/// The heads of the file and its grids at their places, and where each grid's topology goes.
struct Heads {
  std::vector<std::pair<std::uint64_t, std::string>> bytes;
  std::vector<std::pair<std::uint64_t, Encoding>> topologies;
  std::uint64_t end = 0;  ///< where the file ends
};

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

  // The heads, once every leaf's size is known: their bytes and places, each grid's leaves' place
  // (buffers) and where the file ends; the topologies' places, made when written (write_heads).
  auto plan_heads = [&](const std::vector<std::vector<std::int64_t>>& blosc_sizes,
                        const std::vector<std::uint64_t>& buffer_bytes) {
    Heads heads;
    heads.bytes.push_back({0, file_head(meta, static_cast<std::int32_t>(grids.size()))});
    std::uint64_t at = heads.bytes.back().second.size();
    std::map<bool, std::size_t> nodes;  // the topologies' sizes, by tile encoding (see write_heads)
    for (std::size_t g = 0; g < grids.size(); ++g) {
      GridHead grid = grid_head(grids[g], layout, compression, blosc_sizes[g]);
      std::string& bytes = grid.bytes;
      const Encoding& e = encodings[g];
      bytes += topology_head(layout, e);
      auto size = nodes.find(e.blosc && !e.half);
      if (size == nodes.end()) size = nodes.emplace(e.blosc && !e.half, topology_nodes_size(layout, e)).first;
      buffers[g] = at + bytes.size() + size->second;
      // The grid starts after its offsets (at its compression), its leaves after the topology.
      const std::int64_t offsets[3] = {static_cast<std::int64_t>(at + grid.offsets_at + 3 * sizeof(std::int64_t)),
                                       static_cast<std::int64_t>(buffers[g]),
                                       static_cast<std::int64_t>(buffers[g] + buffer_bytes[g])};
      std::memcpy(&bytes[grid.offsets_at], offsets, sizeof offsets);
      heads.topologies.push_back({at + bytes.size(), e});
      heads.bytes.push_back({at, std::move(bytes)});
      at = buffers[g] + buffer_bytes[g];
    }
    heads.end = at;
    return heads;
  };
  auto write_heads = [&](const Heads& heads) {
    for (const auto& [at, bytes] : heads.bytes) writer_of_file.write(at, bytes.data(), bytes.size());
    // Grids of the same tile encoding share their topology's nodes and leaf masks.
    std::map<bool, ZeroedVector<char>> nodes;
    for (const auto& [at, e] : heads.topologies) {
      auto tree = nodes.find(e.blosc && !e.half);
      if (tree == nodes.end()) tree = nodes.emplace(e.blosc && !e.half, topology_nodes(layout, e)).first;
      writer_of_file.write(at, tree->second.data(), tree->second.size());
    }
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
  Heads heads;  // without Blosc: planned now, written by a job beside the bands'
  if (!blosc) {
    std::vector<std::uint64_t> buffer_bytes;
    for (const Encoding& e : encodings)
      buffer_bytes.push_back((kLeafMaskBytes + 1) * std::uint64_t(leaves) + layout.voxels * e.value_bytes());
    heads = plan_heads(std::vector<std::vector<std::int64_t>>(grids.size()), buffer_bytes);
    end = heads.end;
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
  // Without Blosc, job 0 writes the heads and topologies (a single thread's work between the passes
  // otherwise), the others a band each.
  const std::size_t first_band = blosc ? 0 : 1;
  parallel_jobs(first_band + bands, threads, [&](std::size_t job, int worker) {
    if (job < first_band) {
      write_heads(heads);
      return;
    }
    const std::size_t b = job - first_band;
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
    const Heads planned = plan_heads(blosc_sizes, buffer_bytes);
    write_heads(planned);
    end = planned.end;
    parallel_jobs(bands, threads, [&](std::size_t b, int) {
      for (std::size_t g = 0; g < grids.size(); ++g)
        write_runs(layout.band_leaves[b], kept[b][g].bytes, kept[b][g].sizes,
                   [&](std::size_t i) { return buffers[g] + offsets[g][i]; });
      kept[b].clear();
      flushes.written();
    }, progress_range(progress, 0.7, 0.85));
  }
  // The UUID, the write-back and the last flush while the last band's flush may still run.
  const std::string uuid = hash.uuid(end);
  file.write(kUuidOffset, uuid.data(), uuid.size());
  file.sync_pieces(end, progress_range(progress, 0.85, 1.0));
  flushes.flush_and_finish();
  out.commit();
  return layout.voxels;
}

}  // namespace ifsforge::detail
