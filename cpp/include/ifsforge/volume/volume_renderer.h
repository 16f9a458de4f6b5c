#pragma once
/// @file The volumetric renderers of the seed's Table 2 (5.13.2) behind one interface, and
/// what they share: the options, the checks on the input and the grid they fill.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ifsforge/core/names.h"
#include "ifsforge/core/progress.h"
#include "ifsforge/model/capabilities.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/volume/volume.h"
#include "ifsforge/volume/voxel_list.h"

namespace ifsforge {

/// Escape time (5.5): which delta of Eq. 55-56 picks the inverse map.
enum class EscapeNorm { Euclidean, Linear };
template <>
struct EnumNames<EscapeNorm> {
  static constexpr const char* what = "escape-time norm (Eq. 55)";
  static constexpr NamedValue<EscapeNorm> values[] = {
      {EscapeNorm::Euclidean, "euclidean"},
      {EscapeNorm::Linear, "linear"}};
};

/// What a range of a renderer's jobs produces: the sorted integer sums of their voxels (which
/// merge exactly with any other range's), the points they plotted and the deepest level reached.
struct VolumeJobsResult {
  VoxelList voxels;
  std::uint64_t points = 0;
  int depth = 0;
};

/// Runs the jobs [first, last) elsewhere (on a cluster) and returns their results as the bytes
/// of encode_volume_jobs (volume/volume_jobs.h), grouped in any way: the merge is exact, so the
/// volume is the same bytes as when they run here. The runner keeps the bytes alive until its
/// next call or its end: the merge reads them in place.
using VolumeJobRunner = std::function<std::vector<std::string_view>(std::uint64_t first, std::uint64_t last)>;

struct VolumeOptions {
  int resolution = 256;       ///< voxels along the longest side of the grid's box
  std::optional<Box3> bounds; ///< the grid's world box; default: the attractor's box, cells aligned to its low corner
  VolumeDensity density = VolumeDensity::Binary;
  /// PRR: recursion depth, every leaf at exactly this depth (0: from the resolution, deepened
  /// while occupancy still changes). DIA: levels of volume rewriting (0: until occupancy
  /// stops changing).
  int depth = 0;
  /// RIA: points to plot (0: doubled until occupancy stops changing).
  std::uint64_t iterations = 0;
  /// ETA: iterations of the inverse maps a voxel must survive (0: from the resolution).
  int escape_bound = 0;
  EscapeNorm escape_norm = EscapeNorm::Euclidean;
  bool escape_pick_max = false;  ///< Eq. 56: the largest delta instead of the smallest
  std::uint64_t seed = 0;        ///< RIA only
  int threads = 0;               ///< 0: every core; the volume never depends on it
  ProgressCallback progress;
  /// Empty: the jobs run here on `threads` threads. Set: the renderer plans, hands every job
  /// to it, and merges (prr and ria; the others throw InputError).
  VolumeJobRunner distribute;
  /// Set: the renderer may give its volume band by band to `bands` instead of building it, and
  /// return it without its voxels (prr does, merging its jobs a band at a time). See
  /// VolumeRenderer::render_bands, which gives every renderer's volume that way.
  VolumeBandSink bands;
};

class VolumeRenderer {
 public:
  virtual ~VolumeRenderer() = default;
  virtual std::string name() const = 0;
  virtual std::string description() const = 0;
  /// @brief The systems it draws: render and run_jobs refuse any other before any work, with an
  /// InputError naming the volume renderers that do draw it.
  virtual Capabilities capabilities() const = 0;
  /// @brief InputError unless capabilities() covers `ifs`.
  void require_handles(const Ifs& ifs) const;
  /// @brief Renders `ifs` (xyz layouts with any extra channels; it must have an attractor).
  Volume render(const Ifs& ifs, const VolumeOptions& options) const;
  /// @brief The volume given to `sink` band by band (VolumeOptions::bands where the renderer
  /// takes it, else the whole rendered volume's bands); returns it without its voxels.
  Volume render_bands(const Ifs& ifs, VolumeOptions options, const VolumeBandSink& sink) const;
  /// @brief Runs jobs [first, last) of the render `options` describe (on `options.threads`
  /// threads), merged into one result as the bytes of encode_volume_jobs: what a cluster's
  /// worker does. InputError for a renderer whose work does not split into independent jobs.
  std::string run_jobs(const Ifs& ifs, const VolumeOptions& options, std::uint64_t first, std::uint64_t last) const;

 protected:
  /// @brief render() and run_jobs() once the system is known to be handled.
  virtual Volume draw(const Ifs& ifs, const VolumeOptions& options) const = 0;
  virtual std::string draw_jobs(const Ifs& ifs, const VolumeOptions& options, std::uint64_t first,
                                std::uint64_t last) const;
};

/// @brief The volumetric renderer called `name` ("prr", "ria", "dia", "eta" or an alias);
/// InputError lists the choices.
const VolumeRenderer& volume_renderer(const std::string& name);
/// @brief Every volumetric renderer, in the order of Table 2's discussion (PRR first).
std::vector<const VolumeRenderer*> volume_renderers();
/// @brief Every volumetric renderer's name and capabilities, in that order.
const std::vector<std::pair<std::string, Capabilities>>& volume_renderer_capabilities();
/// @brief volume_renderer(algorithm).render(ifs, options).
Volume render_volume(const Ifs& ifs, const std::string& algorithm, const VolumeOptions& options);

/// What every volumetric renderer starts from.
struct VolumeSetup {
  Bounds bounds;        ///< the attractor's bounds per channel (all n dimensions)
  VoxelGrid grid;
  ChannelQuantizer quantizer;
  /// A box B holding the attractor (all n dimensions, 1% margin), as the recursion's
  /// image_box wants it: centre and half-extent. Its centre is the point PRR plots.
  std::vector<double> center, half;
  /// A few points of the attractor (all n dimensions) at its corners: the fixed points of the
  /// maps and their images while they are at most 16; of more than 8, those farthest along the
  /// 26 directions of a cube's faces, edges and corners (each costs PRR a product per piece).
  /// Their images reach the corners of a piece.
  std::vector<Point> extremes;
  int threads = 1;
};

/// @brief Checks the input (3 spatial dimensions, resolution, an attractor) and fits the grid.
/// InputError / DivergentSystemError name what is wrong.
VolumeSetup prepare_volume(const Ifs& ifs, const VolumeOptions& options);

/// @brief About how many voxels the attractor occupies on `setup.grid`, estimated before any
/// large allocation so that a render over the memory budget is refused first. A set of
/// box-counting dimension D occupies about res^D voxels: with D from the maps (N pieces
/// shrinking by at most s: D <= log N / -log s) the bound 8 res^D is cheap but loose; when
/// that bound times `bytes_per_voxel` (plus `fixed_bytes`) would not fit the budget, two pilot
/// renders at 32^3 and 64^3 measure the count and its slope instead (the Menger sponge at
/// 729^3: 64 M voxels, where the bound said 1.4 G).
double expected_voxels(const Ifs& ifs, const VolumeOptions& options, const VolumeSetup& setup,
                       double bytes_per_voxel, double fixed_bytes);

/// @brief The attractor's bounds per channel (Ifs::attractor_bounds). `extremes` (optional)
/// receives a few attractor points at its corners (see VolumeSetup). The sample walks on up to
/// `threads` cores: the same bounds.
Bounds volume_bounds(const Ifs& ifs, std::vector<Point>* extremes = nullptr, int threads = 1);

}  // namespace ifsforge
