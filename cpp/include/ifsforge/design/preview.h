#pragma once
/// @file Point clouds for interactive design. The collage theorem (seed chapter 4, Theorem 3,
/// Eq. 41-42) is why designing by editing maps works: the attractor A is the union of its
/// pieces w_i(A), so a user who watches the pieces while moving a map sees exactly the collage
/// the theorem asks them to fit. A preview therefore colours each point by the piece it lies
/// in, or by the layout's colour channels, and outlines each piece's image of the bounding box.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ifsforge/core/names.h"
#include "ifsforge/model/ifs.h"

namespace ifsforge {

/// @brief Pieces: by the map applied last, so the point lies in w_i(A) and the N colours show
/// the collage A = U w_i(A). Channels: the layout's colour channels (gray, RGB, HSI converted,
/// RGBA), normalised as Eq. 101 when they leave [0, 1]. Auto: Channels when the layout has
/// colour channels, else Pieces.
enum class PreviewColoring { Auto, Pieces, Channels };
template <>
struct EnumNames<PreviewColoring> {
  static constexpr const char* what = "preview coloring";
  static constexpr NamedValue<PreviewColoring> values[] = {
      {PreviewColoring::Auto, "auto"},
      {PreviewColoring::Pieces, "pieces"},
      {PreviewColoring::Channels, "channels"}};
};

struct PreviewOptions {
  std::size_t count = 200000;  ///< points in the cloud
  std::uint64_t seed = 0;
  PreviewColoring coloring = PreviewColoring::Auto;
  int highlight = -1;  ///< a map whose piece and frame stay bright while the others are dimmed
  int threads = 0;     ///< 0: all cores; the cloud never depends on it
};

/// What a viewport draws: points with colours, and the collage frames as line segments.
struct PreviewCloud {
  std::size_t count = 0;
  std::vector<float> positions;        ///< count x 3 (x, y, z); z = 0 for planar systems
  std::vector<float> colors;           ///< count x 4, RGBA in [0, 1]
  std::vector<std::uint32_t> pieces;   ///< count: index of the map applied last
  Bounds bounds;                       ///< per channel: min/max (hyperbolic) or 0.1/99.9% quantiles
  std::vector<float> frame_positions;  ///< segment end points, x 3: the box, then w_i(box) for each map
  std::vector<float> frame_colors;     ///< one RGBA per end point
  std::vector<std::uint32_t> frame_pieces;  ///< per end point: the map, or size() for the box itself
  PreviewColoring coloring = PreviewColoring::Pieces;  ///< what `colors` shows (Auto resolved)
};

/// @brief The colour of piece `index` (golden-angle hues, so neighbours differ); dimmed
/// when `dim`.
void piece_color(std::size_t index, bool dim, float* rgba);

/// @brief A seeded random iteration (5.1.1) of `options.count` points split into fixed jobs
/// (one stream per job, each starting on the attractor), so the cloud is identical for any
/// thread count. Throws DivergentSystemError for a system without an attractor.
PreviewCloud preview_cloud(const Ifs& ifs, const PreviewOptions& options = {});

}  // namespace ifsforge
