#pragma once
/// @file POV-Ray's density file (.df3), read by `density_file df3` in media: a 6-byte header of
/// three big-endian uint16 sizes (x, y, z), then one big-endian unsigned voxel per cell of 8, 16
/// or 32 bits, x fastest, then y, then z. POV-Ray maps the grid onto the unit cube.
#include <string>

#include "ifsforge/core/names.h"
#include "ifsforge/volume/volume.h"

namespace ifsforge {

/// What a .df3 holds: the density, or one linear channel of the colour (media coefficients are
/// linear, so a scene multiplies them by these values as they are).
enum class Df3Content { Density, Red, Green, Blue };
template <>
struct EnumNames<Df3Content> {
  static constexpr const char* what = "df3 content";
  static constexpr NamedValue<Df3Content> values[] = {
      {Df3Content::Density, "density"}, {Df3Content::Red, "red"}, {Df3Content::Green, "green"}, {Df3Content::Blue, "blue"}};
};

/// @brief Writes one grid of the volume (atomically), scaled to the full range of `bits` (8, 16
/// or 32) and rounded; empty voxels 0. Density: every voxel's density divided by the largest
/// one. Red, green, blue: the channel of the voxel's display colour ("color" of
/// volume_attributes) made linear (srgb_to_linear), in [0, 1]. InputError for other bits, a side
/// longer than 65535 voxels or a colour asked of a volume without one; FileError when it cannot
/// write. With `border`, one empty voxel surrounds the grid (each side 2 longer): POV-Ray's
/// interpolation puts voxel i at i / n of the unit cube and wraps round from the last voxel to
/// the first, so a bordered grid fades to nothing at its faces as a .vdb does in Blender.
void write_df3(const std::string& path, const Volume& volume, int bits = 8, Df3Content content = Df3Content::Density,
               bool border = false);

}  // namespace ifsforge
