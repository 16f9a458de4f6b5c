#include "ifsforge/geometry/mesh_edges.h"

#include <algorithm>
#include <string>

#include "ifsforge/core/error.h"

namespace ifsforge {

MeshEdges mesh_edges(const std::vector<std::uint32_t>& corners, int face_size, std::size_t vertex_count) {
  if (face_size < 3 || corners.size() % face_size != 0)
    throw InputError("mesh_edges: " + std::to_string(corners.size()) + " corners are not faces of " +
                     std::to_string(face_size));
  const std::size_t k = face_size;
  const auto next = [&](std::size_t c) { return c % k == k - 1 ? c + 1 - k : c + 1; };
  // Bucket every corner's edge under its lower vertex (counting sort: offsets, then fill).
  std::vector<std::uint32_t> offsets(vertex_count + 1, 0);
  for (std::size_t c = 0; c < corners.size(); ++c) {
    const std::uint32_t a = corners[c], b = corners[next(c)];
    if (a >= vertex_count || b >= vertex_count)
      throw InputError("face " + std::to_string(c / k) + " uses vertex " + std::to_string(std::max(a, b)) + " of " +
                       std::to_string(vertex_count));
    if (a == b) throw InputError("face " + std::to_string(c / k) + " repeats vertex " + std::to_string(a));
    ++offsets[std::min(a, b) + 1];
  }
  for (std::size_t v = 0; v < vertex_count; ++v) offsets[v + 1] += offsets[v];
  struct Entry {
    std::uint32_t high, corner;
  };
  std::vector<Entry> entries(corners.size());
  std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
  for (std::size_t c = 0; c < corners.size(); ++c) {
    const std::uint32_t a = corners[c], b = corners[next(c)];
    entries[fill[std::min(a, b)]++] = {std::max(a, b), static_cast<std::uint32_t>(c)};
  }
  // Within a bucket (a handful of entries, in corner order) equal high vertices are one edge.
  MeshEdges out;
  out.edges.reserve(corners.size() / 2 + 1);
  out.corner_edges.resize(corners.size());
  for (std::size_t v = 0; v < vertex_count; ++v) {
    Entry* first = entries.data() + offsets[v];
    Entry* last = entries.data() + offsets[v + 1];
    for (Entry* e = first + 1; e < last; ++e)  // insertion sort by high vertex (stable)
      for (Entry* f = e; f > first && f->high < (f - 1)->high; --f) std::swap(*f, *(f - 1));
    for (Entry* e = first; e != last; ++e) {
      if (e == first || e->high != (e - 1)->high)
        out.edges.push_back({static_cast<std::uint32_t>(v), static_cast<std::uint32_t>(e->high)});
      out.corner_edges[e->corner] = static_cast<std::uint32_t>(out.edges.size() - 1);
    }
  }
  return out;
}

}  // namespace ifsforge
