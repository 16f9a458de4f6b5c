// 3D targets of the fit: OpenVDB grids and voxelised meshes as voxel sets.
#include "ifsforge/io/voxel_target.h"

#include "vdb_trees.h"
#include <openvdb/io/Stream.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <new>

#include "ifsforge/core/error.h"
#include "ifsforge/io/mesh_reader.h"
#include "vdb_archive.h"
#include "vdb_grid.h"

namespace ifsforge {
namespace {

std::string lower_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

/// The voxel set over `box` (world xmin ymin zmin xmax ymax zmax) with `resolution` voxels
/// along its longest side: a voxel is set when its centre is inside, or when a source voxel
/// centre (`marks`, world points) falls in it (so shapes finer than the new voxels survive).
template <typename Inside>
VoxelSet resample(const Box3& box, int resolution, Inside&& inside, const std::vector<openvdb::Vec3d>& marks) {
  const double extent = std::max({box[3] - box[0], box[4] - box[1], box[5] - box[2]});
  VoxelSet out;
  out.grid.voxel_size = extent / resolution;
  out.grid.origin = {box[0], box[1], box[2]};
  for (int a = 0; a < 3; ++a)
    out.grid.dims[a] = std::clamp(static_cast<int>(std::ceil((box[a + 3] - box[a]) / out.grid.voxel_size - 1e-9)), 1,
                                  resolution);
  out.cells.assign(std::size_t(out.grid.dims[0]) * out.grid.dims[1] * out.grid.dims[2], 0);
  for (int k = 0; k < out.grid.dims[2]; ++k)
    for (int j = 0; j < out.grid.dims[1]; ++j)
      for (int i = 0; i < out.grid.dims[0]; ++i)
        if (inside(out.grid.center(i, j, k))) out.cells[out.index(i, j, k)] = 1;
  for (const auto& p : marks) {
    int v[3];
    for (int a = 0; a < 3; ++a)
      v[a] = std::clamp(static_cast<int>(std::floor((p[a] - out.grid.origin[a]) / out.grid.voxel_size)), 0,
                        out.grid.dims[a] - 1);
    out.cells[out.index(v[0], v[1], v[2])] = 1;
  }
  return out;
}

VoxelSet from_vdb(const std::string& path, const VoxelTargetOptions& o) {
  openvdb::FloatGrid::Ptr grid;
  detail::read_vdb_archive<InputError>(path, [&](openvdb::io::Stream& file) {
    const openvdb::GridPtrVecPtr grids = file.getGrids();
    for (const auto& g : *grids) {
      auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g);
      if (f && (!grid || (f->getName() == "density" && grid->getName() != "density"))) grid = f;
    }
  });
  if (!grid) throw InputError("'" + path + "' holds no float grid (a density or level set) to fit");
  const openvdb::math::Transform& t = grid->transform();
  const openvdb::Vec3d h = t.voxelSize();
  if (!t.isLinear() || std::abs(h[0] - h[1]) > 1e-9 * h[0] || std::abs(h[0] - h[2]) > 1e-9 * h[0])
    throw InputError("grid '" + grid->getName() + "' of '" + path + "' has no uniform linear transform (cubic voxels)");
  const bool level_set = grid->getGridClass() == openvdb::GRID_LEVEL_SET;
  auto accessor = grid->getConstAccessor();
  auto in_shape = [&](float v) { return level_set ? v < 0.0f : v > o.density_threshold; };
  std::vector<openvdb::Vec3d> marks;
  openvdb::CoordBBox bounds;
  // The shape's box: its active voxels and tiles (a level set's inside reaches its surface,
  // where the narrow band's active voxels are).
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    if (!in_shape(*it)) continue;
    if (!it.isVoxelValue()) {
      bounds.expand(it.getBoundingBox());
      continue;
    }
    bounds.expand(it.getCoord());
    marks.push_back(t.indexToWorld(it.getCoord()));
  }
  if (bounds.empty()) throw InputError("grid '" + grid->getName() + "' of '" + path + "' holds no shape");
  // Index coordinates are voxel centres: the box reaches half a voxel beyond them.
  const openvdb::Vec3d lo = t.indexToWorld(bounds.min().asVec3d() - 0.5), hi = t.indexToWorld(bounds.max().asVec3d() + 0.5);
  const Box3 box = {std::min(lo[0], hi[0]), std::min(lo[1], hi[1]), std::min(lo[2], hi[2]),
                    std::max(lo[0], hi[0]), std::max(lo[1], hi[1]), std::max(lo[2], hi[2])};
  return resample(box, o.resolution, [&](const std::array<double, 3>& p) {
    const openvdb::Coord c = openvdb::Coord::round(t.worldToIndex(openvdb::Vec3d(p[0], p[1], p[2])));
    return in_shape(accessor.getValue(c));
  }, marks);
}

VoxelSet from_mesh(const std::string& path, const VoxelTargetOptions& o) {
  const TriangleMesh mesh = read_mesh(path);
  Box3 box = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
  std::vector<openvdb::Vec3s> points;
  for (const auto& p : mesh.positions) {
    points.emplace_back(p[0], p[1], p[2]);
    for (int a = 0; a < 3; ++a) box[a] = std::min<double>(box[a], p[a]), box[a + 3] = std::max<double>(box[a + 3], p[a]);
  }
  const double extent = std::max({box[3] - box[0], box[4] - box[1], box[5] - box[2]});
  if (!(extent > 0)) throw InputError("the mesh '" + path + "' encloses no volume (all its vertices coincide)");
  std::vector<openvdb::Vec3I> triangles;
  for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  // The level set on voxels of the target's size, their centres where resample() puts its own.
  const double h = extent / o.resolution;
  auto transform = openvdb::math::Transform::createLinearTransform(h);
  transform->postTranslate(openvdb::Vec3d(box[0] + 0.5 * h, box[1] + 0.5 * h, box[2] + 0.5 * h));
  const auto level_set = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, triangles, 2.0f);
  auto accessor = level_set->getConstAccessor();
  // Inside, or the surface within half a voxel of the centre: a plate thinner than a voxel (the
  // iso-surface of a thin fractal) keeps its voxels although no centre lies inside it.
  const float near = static_cast<float>(0.5 * h);
  VoxelSet out = resample(box, o.resolution, [&](const std::array<double, 3>& p) {
    const openvdb::Coord c = openvdb::Coord::round(transform->worldToIndex(openvdb::Vec3d(p[0], p[1], p[2])));
    return accessor.getValue(c) <= near;
  }, {});
  if (out.count() == 0) throw InputError("the mesh '" + path + "' encloses no voxel at resolution " + std::to_string(o.resolution));
  return out;
}

}  // namespace

VoxelSet read_voxel_target(const std::string& path, const VoxelTargetOptions& o) {
  if (o.resolution < 4 || o.resolution > 1024)
    throw InputError("the target's resolution must be 4..1024 voxels, got " + std::to_string(o.resolution));
  detail::initialize();
  const std::string ext = lower_extension(path);
  if (ext == ".vdb") return from_vdb(path, o);
  if (ext == ".obj" || ext == ".ply" || ext == ".stl" || ext == ".off") return from_mesh(path, o);
  throw InputError("a 3D target is a .vdb, .obj, .ply, .stl or .off file, got '" + path + "'");
}

}  // namespace ifsforge
