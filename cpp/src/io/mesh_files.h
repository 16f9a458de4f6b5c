#pragma once
// PLY (binary) and OBJ written by ifsforge itself (src/io only): OpenMesh's writers copied the
// mesh into its own kernel and formatted one number at a time on one core, and could not be
// stopped.
#include <cstdio>
#include <string>

#include "ifsforge/core/progress.h"
#include "ifsforge/geometry/axes.h"
#include "ifsforge/geometry/triangle_mesh.h"

namespace ifsforge::detail {

/// Binary little-endian PLY: x y z [nx ny nz] [red green blue alpha as uchar] [u v], then faces
/// as "list uchar int". `path` names the file in errors.
void write_ply(std::FILE* file, const std::string& path, const TriangleMesh& mesh, Up up,
               const ProgressCallback& progress);

/// OBJ: per vertex "v" [, "vt"] [, "vn"] (floats in their shortest exact form), then "f" lines
/// with 1-based indices; no colours (OBJ has no standard vertex colour).
void write_obj(std::FILE* file, const std::string& path, const TriangleMesh& mesh, Up up,
               const ProgressCallback& progress);

}  // namespace ifsforge::detail
