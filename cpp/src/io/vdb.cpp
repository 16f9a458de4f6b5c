#include "ifsforge/io/vdb.h"

#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <new>
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
#include "vdb_grid.h"

namespace ifsforge {
namespace {

using detail::initialize;
using detail::make_grid;

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
  detail::read_vdb_archive<FileError>(path, [&](openvdb::io::Stream& file) {
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
  });
  return info;
}

}  // namespace ifsforge
