#include "ifsforge/geometry/mesh_edges.h"

#include <algorithm>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {

MeshEdges mesh_edges(const std::vector<std::uint32_t>& corners, int face_size, std::size_t vertex_count) {
  if (face_size < 3 || corners.size() % face_size != 0)
    throw InputError("mesh_edges: " + std::to_string(corners.size()) + " corners are not faces of " +
                     std::to_string(face_size));
  const std::size_t k = face_size;
  const auto next = [&](std::size_t c) { return c % k == k - 1 ? c + 1 - k : c + 1; };
  for (std::size_t c = 0; c < corners.size(); ++c) {
    const std::uint32_t a = corners[c], b = corners[next(c)];
    if (a >= vertex_count || b >= vertex_count)
      throw InputError("face " + std::to_string(c / k) + " uses vertex " + std::to_string(std::max(a, b)) + " of " +
                       std::to_string(vertex_count));
    if (a == b) throw InputError("face " + std::to_string(c / k) + " repeats vertex " + std::to_string(a));
  }
  struct Entry {
    std::uint32_t high, corner;
  };
  // Every corner's edge goes to the bucket of its lower vertex, in corner order (counting sort).
  // A job owns a block of vertices and reads all corners, keeping its own: the buckets, and so
  // the edges' order, are those of one pass whatever the blocks, so as many jobs as threads.
  struct Block {
    std::uint32_t lo = 0, hi = 0;
    std::vector<std::uint32_t> offsets;  // bucket v - lo: entries [offsets[v - lo], offsets[v - lo + 1])
    std::vector<Entry> entries;
    std::size_t edges = 0, first_edge = 0;
  };
  std::vector<Block> blocks(std::max<std::size_t>(1, std::min<std::size_t>(resolve_threads(0), vertex_count / 4096)));
  parallel_jobs(blocks.size(), 0, [&](std::size_t b, int) {
    Block& block = blocks[b];
    block.lo = static_cast<std::uint32_t>(vertex_count * b / blocks.size());
    block.hi = static_cast<std::uint32_t>(vertex_count * (b + 1) / blocks.size());
    block.offsets.assign(block.hi - block.lo + 1, 0);
    for (std::size_t c = 0; c < corners.size(); ++c) {
      const std::uint32_t low = std::min(corners[c], corners[next(c)]);
      if (low >= block.lo && low < block.hi) ++block.offsets[low - block.lo + 1];
    }
    for (std::size_t v = 1; v < block.offsets.size(); ++v) block.offsets[v] += block.offsets[v - 1];
    block.entries.resize(block.offsets.back());
    std::vector<std::uint32_t> fill(block.offsets.begin(), block.offsets.end() - 1);
    for (std::size_t c = 0; c < corners.size(); ++c) {
      const std::uint32_t a = corners[c], b2 = corners[next(c)], low = std::min(a, b2);
      if (low >= block.lo && low < block.hi)
        block.entries[fill[low - block.lo]++] = {std::max(a, b2), static_cast<std::uint32_t>(c)};
    }
    // Within a bucket (a handful of entries, in corner order) equal high vertices are one edge.
    for (std::size_t v = 0; v + 1 < block.offsets.size(); ++v) {
      Entry* first = block.entries.data() + block.offsets[v];
      Entry* last = block.entries.data() + block.offsets[v + 1];
      for (Entry* e = first + 1; e < last; ++e)  // insertion sort by high vertex (stable)
        for (Entry* f = e; f > first && f->high < (f - 1)->high; --f) std::swap(*f, *(f - 1));
      for (Entry* e = first; e != last; ++e) block.edges += e == first || e->high != (e - 1)->high;
    }
  });
  MeshEdges out;
  std::size_t edges = 0;
  for (Block& block : blocks) {
    block.first_edge = edges;
    edges += block.edges;
  }
  out.edges.resize(edges);
  out.corner_edges.resize(corners.size());
  parallel_jobs(blocks.size(), 0, [&](std::size_t b, int) {
    const Block& block = blocks[b];
    std::size_t edge = block.first_edge;
    for (std::size_t v = 0; v + 1 < block.offsets.size(); ++v) {
      const Entry* first = block.entries.data() + block.offsets[v];
      const Entry* last = block.entries.data() + block.offsets[v + 1];
      for (const Entry* e = first; e != last; ++e) {
        if (e == first || e->high != (e - 1)->high) out.edges[edge++] = {block.lo + static_cast<std::uint32_t>(v), e->high};
        out.corner_edges[e->corner] = static_cast<std::uint32_t>(edge - 1);
      }
    }
  });
  return out;
}

}  // namespace ifsforge
