#pragma once
// The fitting's raster: the target's grid, the collage proxy and the attractor's overlap.
#include <cmath>
#include <cstdint>
#include <vector>

#include "ifsforge/inverse/collage.h"

namespace ifsforge {

/// The plane of fit_ifs (the window [0, W/S] x [0, H/S]) seen through a grid of `raster`
/// cells along the long side.
struct FitGrid {
  double side = 1;             ///< S = max(W, H) of the full picture
  double pixels_per_unit = 1;  ///< cells per unit of the plane
  double ymax = 1;             ///< H / S
  double extent = 1;           ///< the plane's long side (1)
  int width = 1, height = 1;   ///< of the grid

  static FitGrid for_target(const PixelSet& full, int raster) {
    FitGrid g;
    g.side = std::max(full.width, full.height);
    g.pixels_per_unit = raster;
    g.ymax = full.height / g.side;
    g.width = static_cast<int>(std::ceil(full.width * raster / g.side));
    g.height = static_cast<int>(std::ceil(full.height * raster / g.side));
    return g;
  }
  /// Max-pooled: a cell is set when any picture pixel in it is (thin strokes survive).
  PixelSet downsample(const PixelSet& full) const {
    PixelSet out{width, height, std::vector<std::uint8_t>(std::size_t(width) * height)};
    const double f = pixels_per_unit / side;
    for (int y = 0; y < full.height; ++y)
      for (int x = 0; x < full.width; ++x)
        if (full.cells[std::size_t(y) * full.width + x])
          out.cells[std::size_t(std::min(height - 1, int(y * f))) * width + std::min(width - 1, int(x * f))] = 1;
    return out;
  }
  std::array<double, 2> to_plane(double px, double py) const {
    return {px / pixels_per_unit, ymax - py / pixels_per_unit};
  }
  PixelMap pixel_map(const AffineMap& m) const { return to_pixel_map(m, 0.0, ymax, pixels_per_unit); }
};

/// The search's fitness: a Chamfer form of the collage distance (mean instead of max, so that
/// it rewards every pixel that moves the right way), plus how much the copies overlap.
class CollageProxy {
 public:
  struct Scratch {
    std::vector<std::uint16_t> stamp;
    std::vector<std::uint8_t> hits;
    PixelSet collage;
  };
  CollageProxy(const PixelSet& target, double overlap_weight);
  double operator()(const std::vector<PixelMap>& maps, Scratch& scratch) const;
  /// Mean distance (pixels) from the target's image under one map to the target: how far
  /// that copy strays (one map's share of the collage distance, comparable across maps).
  double copy_outside(const PixelMap& map) const;

 private:
  PixelSet target_;
  int pad_;
  double overlap_weight_;
  std::vector<double> distance_to_target_;  ///< on the padded grid, pixels
  std::vector<std::array<float, 2>> samples_;  ///< 2 x 2 sub-pixel samples of the target
  std::vector<std::uint32_t> target_cells_;
};

/// Intersection over union of the chaos game's attractor with `target` (maps in pixel
/// coordinates of its grid); points leaving the grid count against it.
double chaos_iou(const std::vector<PixelMap>& maps, const std::vector<double>& probabilities, const PixelSet& target,
                 std::uint64_t seed, CollageProxy::Scratch& scratch);

}  // namespace ifsforge
