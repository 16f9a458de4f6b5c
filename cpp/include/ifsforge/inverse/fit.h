#pragma once
/// @file Automatic fitting: an IFS whose attractor looks like a target picture (the inverse
/// problem of seed chapter 4). A separable CMA-ES with restarts searches the Eq. 5 parameters
/// of every map under a collage proxy on a small raster, each map kept contractive; the best
/// restart is then refined on the attractor itself, last on its IoU at the picture's resolution.
#include <cstdint>
#include <vector>

#include "ifsforge/core/progress.h"
#include "ifsforge/inverse/distance_transform.h"
#include "ifsforge/model/ifs.h"

namespace ifsforge {

struct FitOptions {
  int maps = 3;                  ///< N
  int raster = 64;               ///< cells along the target's long side during the search
  double max_contraction = 0.9;  ///< every map's s_i (Eq. 8-9) stays at most this
  double overlap_weight = 1.0;   ///< weight of the copies' overlap in the collage proxy
  int restarts = 6;              ///< CMA-ES runs (each from its own initial collage)
  int generations = 150;         ///< per run
  int attractor_generations = 40;  ///< per run, on the attractor after the collage proxy
  int refine_generations = 60;   ///< of the final refinement on the attractor
  int final_generations = 200;   ///< of the last search, on the attractor's IoU at the refinement's grid
  int refine_raster = 256;       ///< cells along the long side during the refinement (at most the picture's)
  double time_limit = 0;         ///< seconds; 0: none (only then is the run independent of speed)
  std::uint64_t seed = 0;
  int threads = 0;
  ProgressCallback progress;
  /// `maps` maps in the target's plane (an earlier fit's, such as the best probe of --maps auto):
  /// when given, the restarts and the refinement are skipped and the last search starts from them.
  std::vector<AffineMap> start;
};

struct FitResult {
  Ifs system;                 ///< fit_ifs: 2D, maps in the target's plane, render.window and size set
  double iou = 0;             ///< of the attractor and the target on the refinement grid
  double proxy = 0;           ///< collage proxy of the result
  std::uint64_t evaluations = 0;
  int restarts = 0;           ///< runs completed
  bool time_limited = false;  ///< the time limit cut the search short
};

/// @brief The target's plane: pixel (i, j) of a W x H picture covers
/// [i, i+1] / S x [H - j - 1, H - j] / S with S = max(W, H), i.e. the window [0, W/S] x [0, H/S].
FitResult fit_ifs(const PixelSet& target, const FitOptions& options);

/// @brief Intersection over union of the attractor of `ifs` (chaos game, seeded) and `target`,
/// on the target's grid laid on the window of fit_ifs.
double attractor_iou(const Ifs& ifs, const PixelSet& target, std::uint64_t seed = 0);

}  // namespace ifsforge
