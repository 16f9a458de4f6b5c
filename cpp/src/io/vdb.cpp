#include "ifsforge/io/vdb.h"

#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>

#include "ifsforge/core/color.h"
#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/io/atomic_file.h"
#include "ifsforge/io/ifs_json.h"
#include "vdb_archive.h"

namespace ifsforge {
namespace {

void initialize() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

/// Voxel (i, j, k) is index coordinate (i, j, k); its centre sits at origin + (i + 1/2) h.
openvdb::math::Transform::Ptr transform_of(const VoxelGrid& grid) {
  auto transform = openvdb::math::Transform::createLinearTransform(grid.voxel_size);
  transform->postTranslate(openvdb::Vec3d(grid.origin[0] + 0.5 * grid.voxel_size,
                                          grid.origin[1] + 0.5 * grid.voxel_size,
                                          grid.origin[2] + 0.5 * grid.voxel_size));
  return transform;
}

openvdb::Coord coord_of(std::uint64_t key) {
  const auto v = VoxelGrid::coord(key);
  return openvdb::Coord(v[0], v[1], v[2]);
}

/// A grid holding value(v) at every voxel v of the volume. Voxels come sorted by (i, j, k), so
/// the voxels of one x-row of leaf nodes (8 values of i) are a contiguous run: rows are filled
/// into new leaves in parallel, then the leaves are added to the tree in row order (the tree
/// is the same whatever the thread count).
template <typename GridT, typename Value>
typename GridT::Ptr make_grid(const Volume& volume, const std::string& name, Value&& value) {
  using Leaf = typename GridT::TreeType::LeafNodeType;
  auto grid = GridT::create();
  grid->setName(name);
  grid->setTransform(transform_of(volume.grid));
  if (volume.size() == 0) return grid;
  // Row r holds the voxels with i in [r DIM, (r + 1) DIM).
  const std::uint64_t rows = static_cast<std::uint64_t>(VoxelGrid::coord(volume.keys.back())[0]) / Leaf::DIM + 1;
  std::vector<std::size_t> first(rows + 1);
  for (std::uint64_t r = 0; r <= rows; ++r)
    first[r] = static_cast<std::size_t>(
        std::lower_bound(volume.keys.begin(), volume.keys.end(), VoxelGrid::key(r * Leaf::DIM, 0, 0)) -
        volume.keys.begin());
  // Leaves of one row are found by their (j, k) block.
  const std::uint64_t blocks_j = static_cast<std::uint64_t>(volume.grid.dims[1]) / Leaf::DIM + 1;
  const std::uint64_t blocks_k = static_cast<std::uint64_t>(volume.grid.dims[2]) / Leaf::DIM + 1;
  std::vector<std::vector<std::unique_ptr<Leaf>>> leaves(rows);
  parallel_jobs(rows, 0, [&](std::size_t r, int) {
    std::vector<Leaf*> block(blocks_j * blocks_k, nullptr);
    for (std::size_t v = first[r]; v < first[r + 1]; ++v) {
      const openvdb::Coord ijk = coord_of(volume.keys[v]);
      Leaf*& leaf = block[(ijk.y() / Leaf::DIM) * blocks_k + ijk.z() / Leaf::DIM];
      if (!leaf) {
        leaves[r].push_back(std::make_unique<Leaf>(ijk & ~(Leaf::DIM - 1), grid->background(), false));
        leaf = leaves[r].back().get();
      }
      leaf->setValueOn(Leaf::coordToOffset(ijk), value(v));
    }
  });
  auto& tree = grid->tree();
  for (auto& row : leaves)
    for (auto& leaf : row) tree.addLeaf(leaf.release());  // the tree owns it from here
  return grid;
}

/// A grid of one attribute, evaluated voxel by voxel from the channel means.
openvdb::GridBase::Ptr attribute_grid(const Volume& volume, const AttributeRecipe& recipe) {
  const int nc = volume.channel_count();
  if (recipe.components == 3) {
    auto grid = make_grid<openvdb::Vec3fGrid>(volume, recipe.name, [&](std::size_t v) {
      openvdb::Vec3f rgb;
      recipe.evaluate(&volume.channels[v * nc], rgb.asPointer());
      // Blender's Principled Volume reads the colour grid as linear (the one colour rule).
      for (int c = 0; c < 3; ++c) rgb[c] = srgb_to_linear(rgb[c]);
      return rgb;
    });
    grid->setVectorType(openvdb::VEC_INVARIANT);
    return grid;
  }
  return make_grid<openvdb::FloatGrid>(volume, recipe.name, [&](std::size_t v) {
    float x;
    recipe.evaluate(&volume.channels[v * nc], &x);
    return x;
  });
}

std::string text(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

}  // namespace

void write_vdb(const std::string& path, const Volume& volume, const VdbWriteOptions& options) {
  initialize();
  check_writable(path);
  const int components = 1 + 3 + volume.channel_count();
  check_memory(volume.size() * (8.0 * components + 16.0), "writing a volume of " + std::to_string(volume.size()) + " voxels");
  openvdb::GridPtrVec grids;
  auto density = make_grid<openvdb::FloatGrid>(volume, "density", [&](std::size_t v) { return volume.density[v]; });
  density->setGridClass(openvdb::GRID_FOG_VOLUME);
  density->setSaveFloatAsHalf(options.half && volume.density_mode == VolumeDensity::Binary);
  grids.push_back(density);
  for (const AttributeRecipe& recipe : attribute_recipes(volume, options.color_scale)) {
    grids.push_back(attribute_grid(volume, recipe));
    grids.back()->setSaveFloatAsHalf(options.half);
  }

  openvdb::MetaMap meta;
  meta.insertMeta("creator", openvdb::StringMetadata("ifsforge"));
  meta.insertMeta("ifsforge_algorithm", openvdb::StringMetadata(volume.algorithm));
  meta.insertMeta("ifsforge_density", openvdb::StringMetadata(name_of(volume.density_mode)));
  meta.insertMeta("ifsforge_depth", openvdb::Int64Metadata(volume.depth));
  meta.insertMeta("ifsforge_points", openvdb::Int64Metadata(static_cast<std::int64_t>(volume.points)));
  meta.insertMeta("ifsforge_voxel_size", openvdb::DoubleMetadata(volume.grid.voxel_size));
  meta.insertMeta("ifsforge_origin", openvdb::Vec3DMetadata(openvdb::Vec3d(
      volume.grid.origin[0], volume.grid.origin[1], volume.grid.origin[2])));
  meta.insertMeta("ifsforge_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(
      volume.grid.dims[0], volume.grid.dims[1], volume.grid.dims[2])));
  std::string ranges;
  for (int c = 0; c < volume.channel_count(); ++c)
    ranges += (c ? " " : "") + volume.channel_names[c] + "=[" + text(volume.channel_lo[c]) + "," +
              text(volume.channel_hi[c]) + "]";
  meta.insertMeta("ifsforge_channel_ranges", openvdb::StringMetadata(ranges));
  if (options.system) {
    meta.insertMeta("ifsforge_system", openvdb::StringMetadata(to_ifs_json(*options.system)));
    meta.insertMeta("ifsforge_name", openvdb::StringMetadata(options.system->name()));
    meta.insertMeta("ifsforge_layout", openvdb::StringMetadata(options.system->layout().text()));
  }
  for (const auto& [key, value] : options.metadata) meta.insertMeta(key, *detail::typed_metadata(value));

  AtomicFile out(path);
  // Inactive values are all background: the active mask alone restores them.
  detail::write_vdb_archive(out.temporary_path(), path, openvdb::GridCPtrVec(grids.begin(), grids.end()), meta,
                            openvdb::io::COMPRESS_ACTIVE_MASK | (options.compress ? openvdb::io::COMPRESS_BLOSC : 0));
  out.commit();
}

VdbFileInfo read_vdb_info(const std::string& path) {
  initialize();
  VdbFileInfo info;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError("cannot read '" + path + "': " + std::strerror(errno));
  try {
    // OpenVDB does not check its reads: past the end of a truncated file it goes on with
    // uninitialised sizes and counts (or returns no grids). A stream that throws on the first
    // short read stops it there; it also means reading the grids whole, not delay-loaded.
    in.exceptions(std::ios::failbit | std::ios::badbit);
    openvdb::io::Stream file(in, /*delayLoad=*/false);
    // Keep both alive while iterating (getMetadata returns a copy).
    const openvdb::MetaMap::Ptr meta = file.getMetadata();
    for (auto it = meta->beginMeta(); it != meta->endMeta(); ++it) info.metadata[it->first] = it->second->str();
    const openvdb::GridPtrVecPtr grids = file.getGrids();
    for (const auto& grid : *grids) {
      VdbGridInfo g;
      g.name = grid->getName();
      g.type = grid->valueType();
      g.active_voxels = grid->activeVoxelCount();
      g.voxel_size = grid->voxelSize()[0];
      const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
      g.index_bounds = {box.min().x(), box.min().y(), box.min().z(), box.max().x(), box.max().y(), box.max().z()};
      info.grids.push_back(g);
    }
  } catch (const openvdb::Exception& e) {
    throw FileError("cannot read '" + path + "' as OpenVDB: " + e.what());
  } catch (const std::ios_base::failure&) {
    throw FileError("cannot read '" + path + "' as OpenVDB: the file is truncated or damaged");
  }
  return info;
}

TriangleMesh volume_to_mesh(const Volume& volume, const IsoSurfaceOptions& options) {
  initialize();
  if (!(options.adaptivity >= 0.0 && options.adaptivity <= 1.0))
    throw InputError("the iso-surface adaptivity must be in [0, 1]");
  if (!std::isfinite(options.iso)) throw InputError("the iso value must be a finite number");
  TriangleMesh mesh;
  if (volume.size() == 0) return mesh;
  check_memory(volume.size() * 120.0, "the iso-surface of a volume of " + std::to_string(volume.size()) + " voxels");
  // The scalar field: occupancy (1 in occupied voxels) or the density, 0 outside.
  auto field = make_grid<openvdb::FloatGrid>(
      volume, "field", [&](std::size_t v) { return options.use_density ? volume.density[v] : 1.0f; });
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*field, points, triangles, quads, options.iso, options.adaptivity);

  mesh.positions.reserve(points.size());
  for (const auto& p : points) mesh.positions.push_back({p.x(), p.y(), p.z()});
  // OpenVDB orients polygons for level sets (inside negative); a fog volume has its inside
  // above the iso value, so every polygon is reversed to face outwards.
  for (const auto& t : triangles) mesh.triangles.push_back({t[2], t[1], t[0]});
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[2], q[1], q[0]});
    mesh.triangles.push_back({q[3], q[2], q[0]});
  }
  compute_normals(mesh);

  // Vertex colours: the occupied voxels among the 8 around the vertex, trilinearly weighted.
  const auto attributes = volume_attributes(volume, options.color_scale);
  const auto color = std::find_if(attributes.begin(), attributes.end(), [](const VolumeAttribute& a) { return a.name == "color"; });
  if (color != attributes.end()) {
    const VoxelGrid& g = volume.grid;
    mesh.colors.resize(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
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
        for (int k = 0; k < 3; ++k) sum[k] += w * color->values[found * 3 + k];
        weight += w;
      }
      for (int k = 0; k < 3; ++k) mesh.colors[v][k] = weight > 0 ? static_cast<float>(sum[k] / weight) : 0.0f;
      mesh.colors[v][3] = 1.0f;
    }
  }
  return mesh;
}

}  // namespace ifsforge
