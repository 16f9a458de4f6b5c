#pragma once
/// @file The edges of a mesh of faces with k corners each (triangles, quads), as a mesh editor
/// stores them: each undirected edge once, and for every corner (face f, corner j) the edge from
/// its vertex to the next corner's.
/// Blender computes the same on import with a hash table; doing it here lets the add-on hand
/// Blender finished arrays.
#include <array>
#include <cstdint>
#include <vector>

namespace ifsforge {

struct MeshEdges {
  std::vector<std::array<std::uint32_t, 2>> edges;  ///< (low, high) vertex, sorted by low then high
  std::vector<std::uint32_t> corner_edges;          ///< k per face: edge of (v[j], v[(j+1)%k])
};

/// @brief The edges of the faces `corners` (k = face_size vertex indices per face, face after
/// face) over `vertex_count` vertices, in linear time (a bucket per low vertex). InputError for
/// an index out of range or a face with a vertex repeated in consecutive corners.
MeshEdges mesh_edges(const std::vector<std::uint32_t>& corners, int face_size, std::size_t vertex_count);

}  // namespace ifsforge
