#include "ifsforge/render/tops_renderer.h"

#include "ifsforge/core/error.h"
#include "ifsforge/render/pixel_space.h"
#include "ifsforge/render/tops.h"
#include "ifsforge/render/color_stealing.h"

namespace ifsforge {

Capabilities TopsRenderer::capabilities() const {
  // Top addresses over the pixels.
  using C = Capabilities;
  return {C::AverageContractive | C::Overlapping | C::Plane};
}

Raster TopsRenderer::draw(const Ifs& ifs, const RenderOptions& options) const {
  if (!options.reference_image || options.reference_image->width < 1)
    throw InputError("the tops renderer needs a reference image (--reference)");
  const Image& picture = *options.reference_image;
  const Ifs reference = options.reference_system ? *options.reference_system : grid_reference_system(ifs.size());
  // The picture covers the reference's unit square, as in colour stealing.
  const Frame picture_frame = Frame::fit(reference, picture.width, picture.height, Window{0, 0, 1, 1});
  const Frame frame = Frame::fit(ifs, options.width, options.height, options.window, options.view);
  TopsOptions o{options.width, options.height, options.iterations, options.seed};
  std::uint64_t points = 0;
  const Image warped = tops_warp(reference, picture_frame, picture, ifs, frame, o, &points);
  Raster raster;
  raster.width = warped.width;
  raster.height = warped.height;
  raster.density.assign(std::size_t(warped.width) * warped.height, 0.0f);
  raster.channels.assign(raster.density.size() * 3, 0.0f);
  for (std::size_t c = 0; c < raster.density.size(); ++c) {
    if (warped.pixels[c * 4 + 3] <= 0) continue;
    raster.density[c] = 1.0f;
    for (int k = 0; k < 3; ++k) raster.channels[c * 3 + k] = warped.pixels[c * 4 + k];
  }
  raster.channel_names = {"r", "g", "b"};
  raster.color_model = ColorModel::Rgb;
  raster.channels_in_unit_range = true;
  raster.points = points;
  raster.pixel_size = frame.pixel_size();
  return raster;
}

}  // namespace ifsforge
