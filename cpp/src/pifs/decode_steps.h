#pragma once
// A plane's 1× decode cut into steps that threads share (the encoder's rate control decodes
// each probe's planes for the residual layer, encoder.cpp): the passes of decoder.cpp and
// deblock.cpp over a range of leaves, and the hierarchical decode as stages of such parts.
#include <cstddef>
#include <vector>

#include "ifsforge/pifs/code.h"
#include "ifsforge/pifs/domain_search.h"

namespace ifsforge {

/// @brief `v` (a length at scale 1) at scale 2^log_scale, log_scale of either sign.
inline int scaled_length(int v, int log_scale) { return log_scale >= 0 ? v << log_scale : v >> -log_scale; }

/// @brief One application of the PIFS operator (Eq. 29) to leaves [begin, end) of `plane`,
/// writing their cells of `dst` at scale 2^l. `from_half`: `src` is the level below (scale
/// 2^(l−1)), where each domain already has the range's size (Baharav's step); otherwise `src`
/// is at the same scale and φ averages 2×2. Leaves write disjoint cells: any split of the
/// leaves, on any threads, gives the same raster.
void apply_leaves(const PifsCode& code, const PifsPlane& plane, int l, const PifsRaster& src, bool from_half,
                  PifsRaster& dst, std::size_t begin, std::size_t end);

/// @brief deblock()'s vertical (or horizontal) edges of leaves [begin, end); the horizontal
/// ones once every vertical one is done. Any split of the leaves gives the same raster.
void deblock_leaves(const PifsCode& code, const PifsPlane& plane, int log_scale, PifsRaster& raster, bool vertical,
                    std::size_t begin, std::size_t end);

/// @brief decode_plane(code, plane, 0, Hierarchical, 0, ·) deblocked at 1× (deblock()), in
/// stages whose parts run side by side: one pass per doubling from the coarsest level's fixed
/// point (made by the constructor: its raster is 1/4^min_log of the plane's), then the vertical
/// and the horizontal edges. The same raster, bit for bit, however the parts are spread.
class PlaneDecodeSteps {
 public:
  /// About 2^16 pixels a part (0.1-0.3 ms): enough parts for two threads to share a pass, few
  /// enough that taking one costs nothing beside it.
  static constexpr std::size_t kPartPixels = std::size_t(1) << 16;
  PlaneDecodeSteps(const PifsCode& code, const PifsPlane& plane, std::size_t part_pixels = kPartPixels);
  /// @brief Parts per stage, in stage order (a stage's parts run only once the stage before it
  /// has ended).
  std::vector<std::size_t> stages() const;
  void run(std::size_t stage, std::size_t part);
  /// @brief The deblocked 1× decode, once every stage has run.
  const PifsRaster& raster() const { return levels_.back(); }

 private:
  const PifsCode& code_;
  const PifsPlane& plane_;
  std::size_t part_pixels_;
  std::vector<PifsRaster> levels_;  ///< the coarsest level's fixed point, then one per doubling
  std::size_t parts(const PifsRaster& r) const;
};

}  // namespace ifsforge
