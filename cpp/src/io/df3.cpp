#include "ifsforge/io/df3.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "ifsforge/core/color.h"
#include "ifsforge/core/error.h"
#include "ifsforge/io/atomic_file.h"

namespace ifsforge {

void write_df3(const std::string& path, const Volume& volume, int bits, Df3Content content, bool border) {
  if (bits != 8 && bits != 16 && bits != 32)
    throw InputError("df3 '" + path + "': bits is 8, 16 or 32 (not " + std::to_string(bits) + ")");
  const int pad = border ? 1 : 0;
  const std::array<int, 3> dims{volume.grid.dims[0] + 2 * pad, volume.grid.dims[1] + 2 * pad, volume.grid.dims[2] + 2 * pad};
  for (int a = 0; a < 3; ++a)
    if (dims[a] - 2 * pad < 1 || dims[a] > 65535)
      throw InputError("df3 '" + path + "': " + std::to_string(dims[a]) + " voxels along an axis (1 to 65535)");
  const std::size_t bytes = std::size_t(bits / 8);
  const std::size_t nx = dims[0], ny = dims[1], nz = dims[2];
  std::vector<unsigned char> data(6 + nx * ny * nz * bytes, 0);
  for (int a = 0; a < 3; ++a) {
    data[2 * a] = static_cast<unsigned char>(dims[a] >> 8);
    data[2 * a + 1] = static_cast<unsigned char>(dims[a] & 0xFF);
  }
  // The level of each voxel in [0, 1]: density over the largest, or a linear colour channel.
  std::vector<float> color;
  int channel = 0;
  float top = 0.0f;
  if (content == Df3Content::Density) {
    for (float d : volume.density) top = std::max(top, d);
  } else {
    for (VolumeAttribute& a : volume_attributes(volume))
      if (a.name == "color") color = std::move(a.values);
    if (color.empty())
      throw InputError("df3 '" + path + "': the volume has no color (its layout has no color channels)");
    channel = content == Df3Content::Red ? 0 : content == Df3Content::Green ? 1 : 2;
    top = 1.0f;
  }
  const double full = bits == 32 ? 4294967295.0 : double((std::uint64_t(1) << bits) - 1);
  for (std::size_t v = 0; v < volume.size(); ++v) {
    const auto c = VoxelGrid::coord(volume.keys[v]);
    const double raw = color.empty() ? double(volume.density[v]) : srgb_to_linear(double(color[v * 3 + channel]));
    const double level = top > 0 ? std::clamp(raw / top, 0.0, 1.0) : 0.0;
    std::uint64_t value = static_cast<std::uint64_t>(std::llround(level * full));
    const std::size_t cell = (std::size_t(c[2] + pad) * ny + std::size_t(c[1] + pad)) * nx + std::size_t(c[0] + pad);  // x fastest
    unsigned char* out = data.data() + 6 + cell * bytes;
    for (std::size_t b = bytes; b-- > 0; value >>= 8) out[b] = static_cast<unsigned char>(value & 0xFF);
  }
  check_writable(path);
  AtomicFile file(path);
  write_bytes(file.file(), reinterpret_cast<const char*>(data.data()), data.size(), path);
  file.commit();
}

}  // namespace ifsforge
