#pragma once
/// @file The triangle mesh every target builds and every mesh writer reads.
#include <array>
#include <cstdint>
#include <vector>

#include "ifsforge/core/progress.h"

namespace ifsforge {

/// In ifsforge's axes (right-handed, z up); the writers turn them into the file's axes.
struct TriangleMesh {
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<float, 3>> normals;   ///< empty, or one per vertex
  std::vector<std::array<float, 4>> colors;    ///< empty, or one RGBA per vertex: display (sRGB) values in [0, 1]
  std::vector<std::array<float, 2>> uvs;       ///< empty, or one per vertex
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< counter-clockwise seen from outside
};

/// @brief Angle-weighted vertex normals from the triangles (independent of the triangulation),
/// in parallel (the same for any thread count); `progress` false cancels (Cancelled).
void compute_normals(TriangleMesh& mesh, const ProgressCallback& progress = nullptr);

}  // namespace ifsforge
