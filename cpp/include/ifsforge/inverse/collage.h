#pragma once
/// @file The collage theorem (seed chapter 4, Theorem 3, Eq. 41-42) on the pixel grid: the
/// Hausdorff distance between a target picture I and its collage U w_i(I), and the bound
/// eps / (1 - s) it gives on the distance from I to the attractor.
#include <array>
#include <optional>
#include <vector>

#include "ifsforge/inverse/distance_transform.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/render/frame.h"
#include "ifsforge/core/image.h"

namespace ifsforge {

/// Share of the border above the threshold from which bright is the background.
constexpr double kBrightBorder = 0.75;

/// @brief The foreground of a picture: pixels whose luminance (times alpha, if any) lies above
/// `threshold`, unless at least kBrightBorder of the border pixels do, then those below. A white
/// shape on black is the shape even where it covers much of the frame (as `ifsforge render`
/// draws attractors); a black shape on white, where it touches less than a quarter of the
/// border. A picture bright throughout is a filled frame. InputError when the picture is empty
/// or dark throughout.
PixelSet foreground(const Image& image, double threshold = 0.5);

/// @brief A planar affine map in continuous pixel coordinates (x right, y down):
/// x' = m[0] x + m[1] y + m[2], y' = m[3] x + m[4] y + m[5].
using PixelMap = std::array<double, 6>;

/// @brief The spatial part of `map` seen through a grid whose pixel (0, 0) has its top-left
/// corner at (xmin, ymax) and whose pixels are 1 / `pixels_per_unit` wide.
PixelMap to_pixel_map(const AffineMap& map, double xmin, double ymax, double pixels_per_unit);

/// @brief Where a target picture lies: on `window`, else the system's render.window, else the
/// attractor's frame (as `render` draws the system at the picture's size).
Frame target_frame(const Ifs& ifs, const PixelSet& target, const std::optional<Window>& window);
/// @brief The maps of `ifs` (a planar system) in the pixel coordinates of `frame`.
std::vector<PixelMap> pixel_maps(const Ifs& ifs, const Frame& frame);

/// @brief The collage U w_i(T) of `target` under `maps`, on the target's grid padded by `pad`
/// pixels on each side (images beyond it land on its edge): a pixel is set when the image of
/// one of the 2 x 2 sub-pixel samples of a target pixel falls in it (sub-samples, so that
/// maps contracting by s < 1 leave no holes in the image of a filled region).
PixelSet collage_pixels(const PixelSet& target, const std::vector<PixelMap>& maps, int pad);

/// @brief The target embedded in its grid padded by `pad` pixels on each side.
PixelSet pad_pixels(const PixelSet& set, int pad);

struct CollageReport {
  double distance_pixels = 0;  ///< eps of Eq. 41: d_H(I, U w_i(I)) in pixels
  double distance = 0;         ///< the same in the units of the system's plane
  double contraction = 0;      ///< s = max_i s_i of the spatial blocks
  double bound = 0;            ///< eps / (1 - s) (Eq. 42), units; +infinity when s >= 1
  double bound_pixels = 0;     ///< the same in pixels
  std::size_t target_pixels = 0, collage_pixels = 0;
  Window window;               ///< where the target lies in the plane
};

/// @brief A target prepared for many collage distances (a design's live value as its maps are
/// edited): the padded target and the distance transform to it are computed once, so each
/// distance() only transforms the collage.
class CollageTarget {
 public:
  /// InputError when the target has no pixels.
  explicit CollageTarget(PixelSet target);
  /// @brief Lays the target on target_frame() and measures its collage under the maps of `ifs` (a 2D system).
  CollageReport distance(const Ifs& ifs, const std::optional<Window>& window = {}) const;
  const PixelSet& pixels() const { return target_; }

 private:
  PixelSet target_;
  int pad_ = 0;  ///< images outside the picture still count, up to half the picture beyond it
  PixelSet padded_;
  std::vector<double> to_target_;  ///< squared distance transform of the padded target
};

/// @brief CollageTarget(target).distance(ifs, window).
CollageReport collage_distance(const Ifs& ifs, const PixelSet& target, const std::optional<Window>& window = {});

}  // namespace ifsforge
