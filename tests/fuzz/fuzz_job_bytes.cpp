// The bytes a cluster's workers send back (ifsforge.distributed): a driver merges whatever
// arrives, so a malformed, truncated or hostile result must end in InputError, never in a read
// past a buffer or an allocation the bytes did not pay for. The first byte picks the reader
// (odd: histogram tiles; even: volume slabs, or with the top bit point recursive leaves) and
// its shape; the rest is the result.
#include "fuzz_common.h"
#include "ifsforge/render/accumulator.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/io/vdb.h"
#include "ifsforge/volume/volume_jobs.h"

#include <unistd.h>

namespace {

/// A contractive system of `channels` channels beside x, y, z (what the merge needs: a layout).
ifsforge::Ifs system_with(int channels) {
  static const char* layouts[] = {"xyz", "xyz+gray", "", "xyz+rgb"};
  const ifsforge::ChannelLayout layout(layouts[channels]);
  std::vector<ifsforge::AffineMap> maps(2, ifsforge::AffineMap(layout.dim()));
  for (auto& m : maps)
    for (int r = 0; r < layout.dim(); ++r) m.a(r, r) = 0.5;
  maps[1].b(0) = 0.5;
  return ifsforge::Ifs("fuzz", layout, maps, {0.5, 0.5});
}

void merge_volume(const std::string& bytes, int mode) {
  const ifsforge::VolumeJobsBytes part(bytes);
  ifsforge::decode_volume_jobs(bytes);
  const int channels = part.channels();
  if (channels == 2 || channels > 3) return;
  const ifsforge::ChannelQuantizer quantizer(std::vector<double>(channels, 0.0), std::vector<double>(channels, 1.0));
  // Twice the same part: every voxel merges with itself, through the bitmap or the sort.
  const auto density = static_cast<ifsforge::VolumeDensity>(mode % 3);
  ifsforge::finish_volume_jobs({part, part}, ifsforge::VoxelGrid{}, system_with(channels), quantizer, density, 1.0, 2);
  // Given band by band to the .vdb writer, as `ifsforge volume -o` merges a cluster's results.
  ifsforge::VoxelGrid grid;
  grid.dims = {300, 40, 40};
  const ifsforge::Volume header = ifsforge::empty_volume(grid, system_with(channels), quantizer, density);
  static const std::string path = "/tmp/ifsforge-fuzz-bands-" + std::to_string(getpid()) + ".vdb";
  ifsforge::give_volume_jobs({part, part}, header, quantizer, 1.0,
                             [&](const ifsforge::Volume& h, std::size_t bands, const ifsforge::VolumeBandLoader& load) {
                               ifsforge::write_vdb(path, h, bands, load);
                             });
}

void merge_image(const std::string& bytes, int shape) {
  const int channels = shape % 4;
  ifsforge::Accumulator acc(16, 16, (shape >> 2) & 1, std::vector<double>(channels, 0.0),
                            std::vector<double>(channels, 1.0));
  if ((shape >> 3) & 1) acc.enable_depth();
  acc.merge_encoded(bytes);
  ifsforge::Raster raster;
  acc.finish(raster, 1);
}

/// Point recursive leaves (shape: channels and depth, fixed depth or the pixel stop) through
/// the renderer's own merge, as a cluster's results reach it.
void merge_leaves(const std::string& bytes, int shape) {
  static const char* layouts[] = {"xy", "xy+gray", "xyz", "xyz+rgb"};
  const ifsforge::ChannelLayout layout(layouts[shape % 4]);
  std::vector<ifsforge::AffineMap> maps(2, ifsforge::AffineMap(layout.dim()));
  for (auto& m : maps)
    for (int r = 0; r < layout.dim(); ++r) m.a(r, r) = 0.5;
  maps[1].b(0) = 0.5;
  ifsforge::RenderOptions o;
  o.width = o.height = 16;
  o.depth = (shape >> 2) & 1 ? 3 : 0;
  o.distribute = [&](std::uint64_t, std::uint64_t, int) { return std::vector<std::string_view>{bytes}; };
  ifsforge::renderer("prr").render(ifsforge::Ifs("fuzz", layout, maps, {0.5, 0.5}), o);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int pick = data[0];
  fuzz::with_text(data + 1, size - 1, [&](const std::string& bytes) {
    if (pick & 1)
      merge_image(bytes, pick >> 1);
    else if (pick & 0x80)
      merge_leaves(bytes, pick >> 1);
    else
      merge_volume(bytes, pick >> 1);
  });
  return 0;
}
