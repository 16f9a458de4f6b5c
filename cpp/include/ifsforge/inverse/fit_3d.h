#pragma once
/// @file Automatic fitting in 3D: an xyz IFS whose attractor fills a target voxel set (the
/// inverse problem of seed chapter 4, one axis more). As in 2D (fit.h), a separable CMA-ES with
/// restarts searches every map's scale per axis, three rotation angles and translation under a
/// 3D collage proxy (Eq. 41) on a coarse grid, polishes each run on the attractor's IoU there,
/// then climbs the attractor's IoU on the finer grid; every map stays contractive.
#include <cstdint>
#include <vector>

#include "ifsforge/core/progress.h"
#include "ifsforge/inverse/distance_transform.h"
#include "ifsforge/inverse/fit.h"
#include "ifsforge/model/ifs.h"

namespace ifsforge {

struct Fit3dOptions {
  int maps = 4;                    ///< N
  int raster = 32;                 ///< voxels along the target's longest side during the search
  int refine_raster = 64;          ///< during the last search (at most the target's)
  double max_contraction = 0.9;    ///< every map's s_i (spectral norm) stays at most this
  double overlap_weight = 1.0;     ///< weight of the copies' overlap in the collage proxy
  int restarts = 4;                ///< CMA-ES runs (each from its own initial collage)
  int generations = 120;           ///< per run, on the collage proxy
  int attractor_generations = 30;  ///< per run, on the attractor's IoU at the search's grid
  int final_generations = 300;     ///< of the last search, on the attractor's IoU at refine_raster
  double time_limit = 0;           ///< seconds; 0: none (only then is the run independent of speed)
  std::uint64_t seed = 0;
  int threads = 0;
  ProgressCallback progress;
  /// `maps` maps in the target's coordinates (an earlier fit's, such as the best probe of --maps
  /// auto): when given, the restarts are skipped and the last search starts from them.
  std::vector<AffineMap> start;
};

/// @brief Fits `options.maps` maps to `target`: a system of layout xyz whose maps act on the
/// target's own coordinates (its grid's box), so `volume` frames the attractor where the target
/// lies; iou on the refinement grid, proxy on the search grid. InputError for an empty target or
/// options out of range.
FitResult fit_3d(const VoxelSet& target, const Fit3dOptions& options);

/// @brief Intersection over union of the attractor of `ifs` (an xyz system; chaos game,
/// seeded) and `target`, on the target's grid.
double attractor_iou_3d(const Ifs& ifs, const VoxelSet& target, std::uint64_t seed = 0);

}  // namespace ifsforge
