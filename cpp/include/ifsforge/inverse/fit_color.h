#pragma once
/// @file The colour of a fitted system (seed Fig. 4.3: one collage per channel). Given the
/// planar maps fitted to a colour picture's shape, each map gets colour rows
/// r' = C_i (r, g, b) + g_i . (x, y) + o_i (likewise g and b; C_i diagonal unless channels mix),
/// affine on the whole point (x, y, r, g, b), solved by least squares
/// so that the colour the picture has at w_i(p) matches the colour map of the picture's colour at p.
#include <array>
#include <cstddef>

#include "ifsforge/core/image.h"
#include "ifsforge/inverse/distance_transform.h"
#include "ifsforge/model/ifs.h"

namespace ifsforge {

struct ColorFitOptions {
  double max_contraction = 0.9;  ///< every map's s_i on the whole (x, y, r, g, b) space stays at most this
  bool positional = true;        ///< colour rows may depend on x, y (a gradient across each copy)
  bool mixing = true;            ///< a channel's row may read the other channels (C_i full, not diagonal)
  double tolerance = 0.1;        ///< color_foreground: a channel difference from the border's colour above this is shape
};

struct ColorFitResult {
  Ifs system;  ///< the planar maps extended to layout xy+rgb; probabilities and render hints kept
  /// Per channel (r, g, b): the RMS of picture(w_i(p)) - (C_i picture(p) + g_i . p + o_i) over the
  /// pixel pairs, the colour collage error (Eq. 41 per channel, as a mean instead of a maximum).
  std::array<double, 3> collage_error{};
  std::size_t samples = 0;  ///< pixel pairs (p, w_i(p)) both in the shape
};

/// @brief The shape of a colour picture: pixels whose colour (or alpha) differs from the border's
/// usual colour (per-channel median of the border pixels) by more than `tolerance` in some
/// channel. InputError when the picture is empty or has no such pixel (or only such pixels).
PixelSet color_foreground(const Image& image, double tolerance = 0.1);

/// @brief True when the picture has colour: three or more channels that are not all equal.
bool has_color(const Image& image);

/// @brief Fits colour rows to the maps of `shape_system` (a planar xy system laid on the picture
/// as `render` draws it: its render.window, else its attractor's frame) against the RGB(A) `picture`
/// on the pixels of `shape`. Colour maps stay contractive: the colour block's and each whole map's
/// contraction factor are at most options.max_contraction (the block shrinks, then the gradient).
/// InputError for a picture without three channels, a shape of another size, or a system that is not xy.
ColorFitResult fit_color(const Ifs& shape_system, const Image& picture, const PixelSet& shape,
                           const ColorFitOptions& options = {});

}  // namespace ifsforge
