// The iso-surface of a volume. OpenVDB's volumeToMesh runs its stages as TBB loops that nothing
// can stop (a large volume's mesh runs for many seconds); here the same stages (VolumeToMesh::operator() for a grid
// without reference grid, surface mask or adaptivity grid) run job by job in parallel_jobs, which
// hears a cancel between jobs of 64 leaves and gives the same mesh for any thread count.
#include "ifsforge/io/vdb.h"

#include "vdb_trees.h"
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "vdb_grid.h"

#if defined(__GNUC__) && !defined(__clang__)
// Of the trees vdb_trees.h declares extern, the members libopenvdb does not export (it inlined
// them everywhere) and this file calls out of line: the destructor's helper of the mesher's two
// index trees. A link error naming another member of a declared tree or grid belongs here.
template void openvdb::tree::Tree<ifsforge::detail::Int16Tree::RootNodeType>::releaseAllAccessors();
template void openvdb::tree::Tree<ifsforge::detail::UInt32Tree::RootNodeType>::releaseAllAccessors();
#endif

namespace ifsforge {
namespace {

namespace vtm = openvdb::tools::volume_to_mesh_internal;
using openvdb::FloatGrid;
using openvdb::FloatTree;
using openvdb::Index32;
using BoolTree = FloatTree::ValueConverter<bool>::Type;
using Int16Tree = FloatTree::ValueConverter<openvdb::Int16>::Type;
using Index32Tree = FloatTree::ValueConverter<Index32>::Type;
using Int16Leaf = Int16Tree::LeafNodeType;
using Index32Leaf = Index32Tree::LeafNodeType;
using Range = tbb::blocked_range<std::size_t>;

// A job of 64 leaves takes about a millisecond: cancels are heard at once. A reduction's job
// builds a tree of its own (internal nodes of up to 32^3 entries) to join at the end: 512 leaves
// (tens of milliseconds) keep those few.
constexpr std::size_t kLeavesPerJob = 64;
constexpr std::size_t kLeavesPerTree = 512;

std::size_t job_count(std::size_t leaves, std::size_t per_job = kLeavesPerJob) {
  return (leaves + per_job - 1) / per_job;
}
Range job_range(std::size_t job, std::size_t leaves, std::size_t per_job = kLeavesPerJob) {
  return Range(job * per_job, std::min(leaves, (job + 1) * per_job));
}

/// One of OpenVDB's loop bodies (operator() const over a range of leaves), job by job.
template <typename Body>
void for_leaves(const Body& body, std::size_t leaves, const ProgressCallback& progress) {
  parallel_jobs(job_count(leaves), 0, [&](std::size_t job, int) { body(job_range(job, leaves)); }, progress);
}

/// One of OpenVDB's reduction bodies (split, operator(), join): a split per job, joined in job
/// order. The bodies build trees of flags whose union does not depend on how the leaves were cut.
template <typename Body>
void reduce_leaves(Body& body, std::size_t leaves, const ProgressCallback& progress) {
  // Bodies hold accessors to their own trees: they cannot move, so they live on the heap.
  std::vector<std::unique_ptr<Body>> parts(job_count(leaves, kLeavesPerTree));
  for (auto& part : parts) part = std::make_unique<Body>(body, tbb::split());
  parallel_jobs(parts.size(), 0, [&](std::size_t job, int) {
    (*parts[job])(job_range(job, leaves, kLeavesPerTree));
  }, progress);
  for (auto& part : parts) {
    body.join(*part);
    part.reset();
  }
}

/// The mesher's polygons as triangles facing outwards, in doVolumeToMesh's order (the pools'
/// triangles, then their quads). OpenVDB orients polygons for level sets (inside negative); a fog
/// volume has its inside above the iso value, so every polygon is reversed. A quad (a, b, c, d)
/// becomes (a, b, c), (a, c, d): the pair Blender joins back into the quad (mesh_data.prepare).
void copy_polygons(const openvdb::tools::PolygonPoolList& pools, std::size_t count, TriangleMesh& mesh,
                   const ProgressCallback& progress) {
  std::vector<std::size_t> first_triangle(count + 1, 0), first_quad(count + 1, 0);
  for (std::size_t p = 0; p < count; ++p) {
    first_triangle[p + 1] = first_triangle[p] + pools[p].numTriangles();
    first_quad[p + 1] = first_quad[p] + pools[p].numQuads();
  }
  const std::size_t triangles = first_triangle[count];
  mesh.triangles.resize(triangles + 2 * first_quad[count]);
  auto* out = mesh.triangles.data();
  parallel_jobs(job_count(count), 0, [&](std::size_t job, int) {
    const Range range = job_range(job, count);
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      const auto& pool = pools[p];
      for (std::size_t i = 0; i < pool.numTriangles(); ++i) {
        const auto& t = pool.triangle(i);
        out[first_triangle[p] + i] = {t[2], t[1], t[0]};
      }
      for (std::size_t i = 0; i < pool.numQuads(); ++i) {
        const auto& q = pool.quad(i);
        const std::size_t at = triangles + 2 * (first_quad[p] + i);
        out[at] = {q[2], q[1], q[0]};
        out[at + 1] = {q[2], q[0], q[3]};
      }
    }
  }, progress);
}

/// volumeToMesh(grid, ..., iso, adaptivity) into `mesh` (positions and triangles). The shares of
/// `progress` follow the stages' times at 256^3 (Menger sponge).
void mesh_field(const FloatGrid& grid, double iso, double adaptivity, TriangleMesh& mesh,
                const ProgressCallback& progress) {
  const FloatTree& input = grid.tree();
  const float isovalue = static_cast<float>(iso);
  const bool adaptive = adaptivity > 1e-7;
  const bool invert = grid.getGridClass() != openvdb::GRID_LEVEL_SET;

  BoolTree intersection(false);  // the cells the surface crosses
  {
    std::vector<const FloatTree::LeafNodeType*> leaves;
    input.getNodes(leaves);
    vtm::LeafNodeVoxelOffsets offsets;
    offsets.constructOffsetList<FloatTree::LeafNodeType>();
    vtm::IdentifyIntersectingVoxels<FloatTree> body(input, leaves, offsets, intersection, isovalue);
    reduce_leaves(body, leaves.size(), progress_range(progress, 0.0, 0.25));
    vtm::maskActiveTileBorders(input, isovalue, intersection);
  }
  if (intersection.empty()) return;

  Int16Tree signs(0);  // each crossed cell's corner signs and edge flags
  Index32Tree indices(std::numeric_limits<Index32>::max());
  {
    std::vector<const BoolTree::LeafNodeType*> leaves;
    intersection.getNodes(leaves);
    vtm::ComputeAuxiliaryData<FloatTree> body(input, leaves, signs, indices, isovalue);
    reduce_leaves(body, leaves.size(), progress_range(progress, 0.25, 0.5));
  }
  intersection.clear();
  std::vector<Index32Leaf*> index_leaves;
  indices.getNodes(index_leaves);
  std::vector<Int16Leaf*> sign_leaves;
  signs.getNodes(sign_leaves);
  const std::size_t leaves = sign_leaves.size();

  // Points per leaf (after merging flat regions when adaptive), then each leaf's first point.
  std::unique_ptr<Index32[]> offsets(new Index32[leaves]);
  if (adaptive) {
    vtm::MergeVoxelRegions<FloatGrid> merge(grid, indices, index_leaves, sign_leaves, isovalue,
                                            static_cast<float>(adaptivity), invert);
    for_leaves(merge, leaves, progress_range(progress, 0.5, 0.55));
    for_leaves(vtm::AdaptiveLeafNodePointCount<Index32Leaf>(index_leaves, sign_leaves, offsets), leaves,
               progress_range(progress, 0.55, 0.6));
  } else {
    for_leaves(vtm::LeafNodePointCount<Int16Leaf::LOG2DIM>(sign_leaves, offsets), leaves,
               progress_range(progress, 0.5, 0.6));
  }
  std::size_t points = 0;
  for (std::size_t n = 0; n < leaves; ++n) {
    const Index32 count = offsets[n];
    offsets[n] = static_cast<Index32>(points);
    points += count;
  }
  if (points > std::numeric_limits<Index32>::max())
    throw InputError("the iso-surface has more vertices than 32-bit indices address");

  openvdb::tools::PointList point_list(new openvdb::Vec3s[points]);
  for_leaves(vtm::ComputePoints<FloatTree>(point_list.get(), input, index_leaves, sign_leaves, offsets,
                                           grid.transform(), iso),
             leaves, progress_range(progress, 0.6, 0.75));

  openvdb::tools::PolygonPoolList pools(new openvdb::tools::PolygonPool[leaves]);
  if (adaptive)
    for_leaves(vtm::ComputePolygons<Int16Tree, vtm::AdaptivePrimBuilder>(sign_leaves, signs, indices, pools, invert),
               leaves, progress_range(progress, 0.75, 0.85));
  else
    for_leaves(vtm::ComputePolygons<Int16Tree, vtm::UniformPrimBuilder>(sign_leaves, signs, indices, pools, invert),
               leaves, progress_range(progress, 0.75, 0.85));
  signs.clear();
  indices.clear();
  // Moves points off edges they cross over: adaptive meshes only, as in volumeToMesh.
  if (adaptive) vtm::relaxDisorientedTriangles(invert, input, grid.transform(), pools, leaves, point_list, points);

  mesh.positions.resize(points);
  parallel_jobs(job_count(points), 0, [&](std::size_t job, int) {
    const Range range = job_range(job, points);
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const openvdb::Vec3s& p = point_list[v];
      mesh.positions[v] = {p.x(), p.y(), p.z()};
    }
  }, progress_range(progress, 0.85, 0.9));
  point_list.reset();
  copy_polygons(pools, leaves, mesh, progress_range(progress, 0.9, 1.0));
}

/// Vertex colours: the occupied voxels among the 8 around each vertex, trilinearly weighted.
void color_vertices(const Volume& volume, const VolumeAttribute& color, TriangleMesh& mesh,
                    const ProgressCallback& progress) {
  const VoxelGrid& g = volume.grid;
  mesh.colors.resize(mesh.positions.size());
  constexpr std::size_t kVerticesPerJob = 1 << 14;
  const std::size_t count = mesh.positions.size();
  parallel_jobs((count + kVerticesPerJob - 1) / kVerticesPerJob, 0, [&](std::size_t job, int) {
    const std::size_t end = std::min(count, (job + 1) * kVerticesPerJob);
    for (std::size_t v = job * kVerticesPerJob; v < end; ++v) {
      double u[3];
      std::int64_t base[3];
      for (int a = 0; a < 3; ++a) {
        u[a] = (mesh.positions[v][a] - g.origin[a]) / g.voxel_size - 0.5;
        base[a] = static_cast<std::int64_t>(std::floor(u[a]));
        u[a] -= static_cast<double>(base[a]);
      }
      double sum[3] = {0, 0, 0}, weight = 0.0;
      for (int corner = 0; corner < 8; ++corner) {
        std::int64_t c[3];
        double w = 1.0;
        for (int a = 0; a < 3; ++a) {
          const int bit = (corner >> a) & 1;
          c[a] = base[a] + bit;
          w *= bit ? u[a] : 1.0 - u[a];
        }
        if (c[0] < 0 || c[1] < 0 || c[2] < 0) continue;
        const std::size_t found = volume.find(VoxelGrid::key(c[0], c[1], c[2]));
        if (found == volume.size()) continue;
        w = std::max(w, 1e-6);  // a vertex on a face still sees the voxel behind it
        for (int k = 0; k < 3; ++k) sum[k] += w * color.values[found * 3 + k];
        weight += w;
      }
      for (int k = 0; k < 3; ++k) mesh.colors[v][k] = weight > 0 ? static_cast<float>(sum[k] / weight) : 0.0f;
      mesh.colors[v][3] = 1.0f;
    }
  }, progress);
}

}  // namespace

TriangleMesh volume_to_mesh(const Volume& volume, const IsoSurfaceOptions& options) {
  detail::initialize();
  if (!(options.adaptivity >= 0.0 && options.adaptivity <= 1.0))
    throw InputError("the iso-surface adaptivity must be in [0, 1]");
  if (!std::isfinite(options.iso)) throw InputError("the iso value must be a finite number");
  TriangleMesh mesh;
  if (volume.size() == 0) return mesh;
  check_memory(volume.size() * 120.0, "the iso-surface of a volume of " + std::to_string(volume.size()) + " voxels");
  const ProgressCallback& progress = options.progress;
  // The scalar field: occupancy (1 in occupied voxels) or the density, 0 outside.
  {
    auto field = detail::make_grid<FloatGrid>(
        volume, "field", [&](std::size_t v) { return options.use_density ? volume.density[v] : 1.0f; },
        progress_range(progress, 0.0, 0.1));
    mesh_field(*field, options.iso, options.adaptivity, mesh, progress_range(progress, 0.1, 0.75));
  }
  if (options.normals) compute_normals(mesh, progress_range(progress, 0.75, 0.9));

  const auto attributes = volume_attributes(volume, options.color_scale);
  const auto color = std::find_if(attributes.begin(), attributes.end(), [](const VolumeAttribute& a) { return a.name == "color"; });
  if (color != attributes.end()) color_vertices(volume, *color, mesh, progress_range(progress, 0.9, 1.0));
  return mesh;
}

}  // namespace ifsforge
