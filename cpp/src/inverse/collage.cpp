#include "ifsforge/inverse/collage.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ifsforge/core/error.h"

namespace ifsforge {

PixelSet foreground(const Image& image, double threshold) {
  if (image.width < 1 || image.height < 1 || image.channels < 1) throw InputError("the target picture is empty");
  const int c = image.channels;
  const bool alpha = c == 2 || c == 4;
  auto value = [&](int x, int y) {
    double v = c >= 3 ? 0.2126 * image.at(x, y, 0) + 0.7152 * image.at(x, y, 1) + 0.0722 * image.at(x, y, 2)
                      : image.at(x, y, 0);
    return alpha ? v * image.at(x, y, c - 1) : v;
  };
  std::size_t above = 0, border = 0;
  for (int x = 0; x < image.width; ++x)
    for (int y : {0, image.height - 1}) above += value(x, y) > threshold, ++border;
  for (int y = 1; y + 1 < image.height; ++y)
    for (int x : {0, image.width - 1}) above += value(x, y) > threshold, ++border;
  // A shape may touch the frame (every tightly framed render does, over up to half its border
  // and more): only a border nearly all bright makes bright the background.
  const bool bright_background = double(above) >= kBrightBorder * double(border);
  PixelSet out{image.width, image.height, std::vector<std::uint8_t>(std::size_t(image.width) * image.height)};
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      out.cells[std::size_t(y) * image.width + x] = (value(x, y) > threshold) != bright_background;
  const std::size_t n = out.count();
  if (n == 0 && bright_background) {  // bright throughout: a filled frame
    std::fill(out.cells.begin(), out.cells.end(), std::uint8_t(1));
    return out;
  }
  if (n == 0 || n == out.cells.size())
    throw InputError("the target picture has no shape: every pixel is on one side of the threshold " +
                     std::to_string(threshold));
  return out;
}

PixelMap to_pixel_map(const AffineMap& w, double xmin, double ymax, double k) {
  // P(x, y) = (k (x - xmin), k (ymax - y)); the pixel map is P o w o P^-1.
  const double a = w.a(0, 0), b = w.a(0, 1), c = w.a(1, 0), d = w.a(1, 1), e = w.b(0), f = w.b(1);
  return {a, -b, k * (a * xmin + b * ymax + e - xmin), -c, d, k * (ymax - c * xmin - d * ymax - f)};
}

PixelSet pad_pixels(const PixelSet& set, int pad) {
  const int W = set.width + 2 * pad, H = set.height + 2 * pad;
  PixelSet out{W, H, std::vector<std::uint8_t>(std::size_t(W) * H)};
  for (int y = 0; y < set.height; ++y)
    std::copy_n(set.cells.begin() + std::size_t(y) * set.width, set.width,
                out.cells.begin() + std::size_t(y + pad) * W + pad);
  return out;
}

PixelSet collage_pixels(const PixelSet& target, const std::vector<PixelMap>& maps, int pad) {
  const int W = target.width + 2 * pad, H = target.height + 2 * pad;
  PixelSet out{W, H, std::vector<std::uint8_t>(std::size_t(W) * H)};
  for (int y = 0; y < target.height; ++y)
    for (int x = 0; x < target.width; ++x) {
      if (!target.cells[std::size_t(y) * target.width + x]) continue;
      for (const PixelMap& m : maps)
        for (double sy : {0.25, 0.75})
          for (double sx : {0.25, 0.75}) {
            const double px = x + sx, py = y + sy;
            const double qx = m[0] * px + m[1] * py + m[2] + pad, qy = m[3] * px + m[4] * py + m[5] + pad;
            const int ix = static_cast<int>(std::clamp(std::floor(qx), 0.0, W - 1.0));
            const int iy = static_cast<int>(std::clamp(std::floor(qy), 0.0, H - 1.0));
            out.cells[std::size_t(iy) * W + ix] = 1;
          }
    }
  return out;
}

Frame target_frame(const Ifs& ifs, const PixelSet& target, const std::optional<Window>& window) {
  std::optional<Window> w = window;
  const auto& saved = ifs.render_defaults().window;
  if (!w && saved.size() == 4) w = Window{saved[0], saved[1], saved[2], saved[3]};
  return Frame::fit(ifs, target.width, target.height, w);
}

std::vector<PixelMap> pixel_maps(const Ifs& ifs, const Frame& frame) {
  std::vector<PixelMap> maps;
  for (const AffineMap& m : ifs.maps())
    maps.push_back(to_pixel_map(m, frame.window().xmin, frame.window().ymax, 1.0 / frame.pixel_size()));
  return maps;
}

CollageTarget::CollageTarget(PixelSet target) : target_(std::move(target)) {
  if (target_.count() == 0) throw InputError("the target has no pixels");
  // Images outside the picture still count: pad by half the picture, where copies that stray
  // further are pinned to the edge (their distance is then at least that half).
  pad_ = std::max(target_.width, target_.height) / 2;
  padded_ = pad_pixels(target_, pad_);
  to_target_ = squared_distance_transform(padded_);
}

CollageReport CollageTarget::distance(const Ifs& ifs, const std::optional<Window>& window) const {
  ifs.require_affine("the collage distance");
  if (ifs.spatial_dims() != 2)
    throw InputError("the collage distance is defined here for planar systems; system '" + ifs.name() + "' is " +
                     std::to_string(ifs.spatial_dims()) + "D in space");
  const Frame frame = target_frame(ifs, target_, window);
  const PixelSet collage = collage_pixels(target_, pixel_maps(ifs, frame), pad_);
  CollageReport r;
  r.window = frame.window();
  r.target_pixels = target_.count();
  r.collage_pixels = collage.count();
  // Eq. 12: the larger of the two directed distances; the one to the target reuses its transform.
  double collage_to_target = 0;
  for (std::size_t i = 0; i < to_target_.size(); ++i)
    if (collage.cells[i]) collage_to_target = std::max(collage_to_target, to_target_[i]);
  r.distance_pixels = std::max(directed_hausdorff(padded_, collage), std::sqrt(collage_to_target));
  r.distance = r.distance_pixels * frame.pixel_size();
  const auto s = ifs.spatial_contraction_factors();
  r.contraction = s.empty() ? 0.0 : *std::max_element(s.begin(), s.end());
  const double inf = std::numeric_limits<double>::infinity();
  r.bound_pixels = r.contraction < 1 ? r.distance_pixels / (1 - r.contraction) : inf;
  r.bound = r.contraction < 1 ? r.distance / (1 - r.contraction) : inf;
  return r;
}

CollageReport collage_distance(const Ifs& ifs, const PixelSet& target, const std::optional<Window>& window) {
  return CollageTarget(target).distance(ifs, window);
}

}  // namespace ifsforge
