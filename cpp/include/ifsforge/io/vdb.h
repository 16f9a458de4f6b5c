#pragma once
/// @file OpenVDB files and iso-surfaces of volumes. OpenVDB stays behind this header (and its
/// .cpp files under src/io, the only ones that include it).
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ifsforge/core/progress.h"
#include "ifsforge/io/mesh.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/volume/volume.h"
#include "ifsforge/volume/volume_renderer.h"

namespace ifsforge {

struct VdbWriteOptions {
  ColorScale color_scale = ColorScale::Auto;
  /// The system the volume was rendered from: its ifsforge/1 JSON, name and layout go into
  /// the file's metadata (ifsforge_system, ifsforge_name, ifsforge_layout).
  const Ifs* system = nullptr;
  /// Extra file metadata (string values).
  std::map<std::string, std::string> metadata;
  /// Store the [0, 1] grids (colour, gray, alpha, ..., and a binary density) as 16-bit
  /// halves: relative error <= 2^-11, far below an 8-bit colour step, and half the bytes.
  /// Hits and measure densities stay 32-bit floats.
  bool half = true;
  /// Blosc-compress the leaf buffers: smaller files, slower to write.
  bool compress = false;
  /// Reports the fraction written; false cancels (Cancelled, and no file is left).
  ProgressCallback progress;
  /// Threads that write (0: every core); the file never depends on it.
  int threads = 0;
  /// Added to every position of the grids' transform: the file's coordinates are the system's
  /// plus this (minus the grid box's centre puts the box around the file's origin, where a
  /// Blender object's pivot sits). Recorded as ifsforge_translation when not zero.
  std::array<double, 3> translation{0.0, 0.0, 0.0};
};

/// @brief Writes `volume` as a .vdb: FloatGrid "density" (a fog volume), Vec3fGrid "color"
/// (linear RGB: srgb_to_linear of the display colour) when the layout has colour, FloatGrids
/// for the other channels ("gray", "alpha", ...; see volume_attributes). Every grid has the
/// same active voxels and a transform that puts voxel (i, j, k)'s centre at
/// origin + (i + 1/2, j + 1/2, k + 1/2) * voxel_size + options.translation in the system's
/// coordinates. File metadata describes the volume (algorithm, depth, points,
/// density, grid origin, voxel size and dimensions, channel ranges), the source system when
/// given, and options.metadata. The grids' leaves are built in parallel (the file does not
/// depend on the thread count). Atomic; FileError when it cannot write.
void write_vdb(const std::string& path, const Volume& volume, const VdbWriteOptions& options = {});

/// @brief write_vdb for a volume given band by band (too large to hold): `header` is the volume
/// without its voxels (grid, density mode, channels and their ranges, algorithm, depth, points)
/// and `load` gives its `bands` bands (see VolumeBandLoader). The same file as write_vdb of the
/// whole volume, holding a band per thread and 100 bytes per leaf of 8^3 voxels. Returns the
/// voxels written.
std::uint64_t write_vdb(const std::string& path, const Volume& header, std::size_t bands, const VolumeBandLoader& load,
                        const VdbWriteOptions& options = {});

/// @brief Renders `ifs` with `algorithm` (render_volume) straight into the .vdb at `path`:
/// PRR gives its volume band by band as it merges its jobs (here or from a cluster, see
/// VolumeOptions::distribute), so that no more than a band is ever held; the others render
/// the volume, then write it. The same file as write_vdb(path, render_volume(...)). Returns the
/// volume without its voxels; `voxels` (optional) receives their number.
Volume render_volume_to_vdb(const std::string& path, const Ifs& ifs, const std::string& algorithm,
                            const VolumeOptions& options, const VdbWriteOptions& vdb = {}, std::uint64_t* voxels = nullptr);

struct VdbGridInfo {
  std::string name, type;       ///< e.g. "density", "float"; "color", "vec3s"
  std::uint64_t active_voxels = 0;
  double voxel_size = 0.0;
  std::array<int, 6> index_bounds{};  ///< active voxels: imin jmin kmin imax jmax kmax
};
struct VdbFileInfo {
  std::vector<VdbGridInfo> grids;
  std::map<std::string, std::string> metadata;  ///< file metadata, values as text
};
/// @brief What a .vdb holds (any .vdb, not only ours); FileError when it cannot be read.
VdbFileInfo read_vdb_info(const std::string& path);

struct IsoSurfaceOptions {
  /// The level of the surface: of the occupancy (1 in occupied voxels, 0 elsewhere) by
  /// default, or of the density grid when use_density is set.
  double iso = 0.5;
  bool use_density = false;
  /// 0: every voxel-sized polygon; up to 1: merge flat regions (fewer triangles).
  double adaptivity = 0.0;
  ColorScale color_scale = ColorScale::Auto;
  /// Per-vertex normals (compute_normals); off leaves TriangleMesh::normals empty, for callers
  /// that derive their own (Blender's smooth shading).
  bool normals = true;
  /// Reports the fraction done; false cancels (Cancelled). Checked at least every 0.1 s.
  ProgressCallback progress;
};

/// @brief The iso-surface of a volume (OpenVDB's volume-to-mesh, seed 7's iso-surfaces) as
/// triangles counter-clockwise seen from outside, in the system's coordinates, with normals
/// and, when the volume has colour, per-vertex RGBA display values: the colours of the occupied voxels around
/// each vertex, trilinearly weighted. A quad of the mesher becomes the triangles (a, b, c),
/// (a, c, d), in that order. Every stage runs in parallel jobs (the mesh does not depend on the
/// thread count) and stops within a job's time of a cancel.
TriangleMesh volume_to_mesh(const Volume& volume, const IsoSurfaceOptions& options = {});

}  // namespace ifsforge
