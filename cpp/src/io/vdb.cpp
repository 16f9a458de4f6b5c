#include "ifsforge/io/vdb.h"

#include "vdb_trees.h"
#include <openvdb/io/Stream.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "ifsforge/core/color.h"
#include "ifsforge/core/error.h"
#include "ifsforge/io/atomic_file.h"
#include "ifsforge/io/ifs_json.h"
#include "vdb_archive.h"
#include "vdb_grid.h"
#include "vdb_srgb.h"
#include "vdb_stream.h"

namespace ifsforge {
namespace {

using detail::initialize;

/// Voxels ahead whose channels a leaf's values fetch early.
constexpr std::size_t kAhead = 16;

/// The empty grids of the file and how each band's values are made: the density, then one grid
/// per exported attribute (volume_attributes' order).
std::vector<detail::StreamGrid> stream_grids(const Volume& header, const VdbWriteOptions& options) {
  auto make = [&](openvdb::GridBase::Ptr grid, const std::string& name, bool half) {
    grid->setName(name);
    grid->setTransform(detail::transform_of(header.grid));
    grid->transform().postTranslate(openvdb::Vec3d(options.translation[0], options.translation[1], options.translation[2]));
    grid->setSaveFloatAsHalf(half);
    return grid;
  };
  std::vector<detail::StreamGrid> grids;
  auto density = make(openvdb::FloatGrid::create(), "density", options.half && header.density_mode == VolumeDensity::Binary);
  density->setGridClass(openvdb::GRID_FOG_VOLUME);
  grids.push_back({density, 1,
                   [](const VoxelSpan& band, const std::uint32_t* voxels, std::size_t count, float* values) {
                     for (std::size_t i = 0; i < count; ++i) values[i] = band.density[voxels[i]];
                   },
                   nullptr, header.density_mode == VolumeDensity::Binary ? std::optional<float>(1.0f) : std::nullopt});
  const int nc = header.channel_count();
  for (const AttributeRecipe& recipe : attribute_recipes(header, options.color_scale)) {
    openvdb::GridBase::Ptr grid;
    if (recipe.components == 3) {
      auto rgb = openvdb::Vec3fGrid::create();
      rgb->setVectorType(openvdb::VEC_INVARIANT);
      grid = rgb;
    } else {
      grid = openvdb::FloatGrid::create();
    }
    detail::StreamGrid g{make(grid, recipe.name, options.half), recipe.components,
                         [recipe, nc](const VoxelSpan& band, const std::uint32_t* voxels, std::size_t count, float* values) {
                           for (std::size_t i = 0; i < count; ++i) {
                             if (i + kAhead < count) __builtin_prefetch(band.channels + std::size_t(voxels[i + kAhead]) * nc);
                             float* out = values + i * recipe.components;
                             recipe.evaluate(band.channels + std::size_t(voxels[i]) * nc, out);
                             // Blender's Principled Volume reads the colour grid as linear (the one colour rule).
                             if (recipe.components == 3)
                               for (int c = 0; c < 3; ++c) out[c] = srgb_to_linear(out[c]);
                           }
                         },
                         nullptr, std::nullopt};
    // As halves, the linear colour comes from LinearHalves' thresholds rather than powf: the same
    // bits. RGB channels (the usual colour) are scaled as AttributeRecipe::evaluate scales them,
    // without its call per voxel.
    if (recipe.components == 3 && options.half)
      g.halves = [recipe, nc, &linear = detail::LinearHalves::get()](const VoxelSpan& band, const std::uint32_t* voxels,
                                                                    std::size_t count, std::uint16_t* halves) {
        const bool rgb = recipe.source == AttributeRecipe::Source::Rgb;
        double a[3] = {}, b[3] = {};
        for (int c = 0; c < 3 && rgb; ++c) a[c] = recipe.scale[recipe.first + c], b[c] = recipe.offset[recipe.first + c];
        for (std::size_t i = 0; i < count; ++i) {
          // A leaf's voxels lie in 64 runs across its band: their channels are fetched ahead.
          if (i + kAhead < count) __builtin_prefetch(band.channels + std::size_t(voxels[i + kAhead]) * nc);
          const float* channels = band.channels + std::size_t(voxels[i]) * nc;
          float unit[3];
          if (rgb) {
            for (int c = 0; c < 3; ++c) unit[c] = static_cast<float>(std::clamp(a[c] * channels[recipe.first + c] + b[c], 0.0, 1.0));
          } else {
            recipe.evaluate(channels, unit);
          }
          for (int c = 0; c < 3; ++c) halves[i * 3 + c] = linear(unit[c]);
        }
      };
    grids.push_back(std::move(g));
  }
  return grids;
}

std::string text(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

openvdb::MetaMap file_metadata(const Volume& volume, const VdbWriteOptions& options) {
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
  const auto& t = options.translation;
  if (t[0] != 0.0 || t[1] != 0.0 || t[2] != 0.0)
    meta.insertMeta("ifsforge_translation", openvdb::Vec3DMetadata(openvdb::Vec3d(t[0], t[1], t[2])));
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
  return meta;
}

}  // namespace

std::uint64_t write_vdb(const std::string& path, const Volume& header, std::size_t bands,
                        const VolumeBandLoader& load, const VdbWriteOptions& options) {
  initialize();
  check_writable(path);
  // Inactive values are all background: the active mask alone restores them.
  return detail::write_vdb_bands(path, header.grid, file_metadata(header, options), stream_grids(header, options), bands,
                                 load, openvdb::io::COMPRESS_ACTIVE_MASK | (options.compress ? openvdb::io::COMPRESS_BLOSC : 0),
                                 options.threads, options.progress);
}

void write_vdb(const std::string& path, const Volume& volume, const VdbWriteOptions& options) {
  write_vdb(path, volume, volume_bands(volume.grid), band_loader(volume), options);
}

Volume render_volume_to_vdb(const std::string& path, const Ifs& ifs, const std::string& algorithm,
                            const VolumeOptions& options, const VdbWriteOptions& vdb, std::uint64_t* voxels) {
  check_writable(path);  // before the render
  VdbWriteOptions w = vdb;
  if (options.progress) w.progress = progress_range(options.progress, 0.95, 1.0);  // PRR's last 5%: its merge
  w.threads = options.threads;
  std::uint64_t written = 0;
  Volume header = volume_renderer(algorithm).render_bands(
      ifs, options, [&](const Volume& h, std::size_t bands, const VolumeBandLoader& load) {
        written = write_vdb(path, h, bands, load, w);
      });
  if (voxels) *voxels = written;
  return header;
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
