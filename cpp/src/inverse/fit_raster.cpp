#include "fit_raster.h"

#include <algorithm>

#include "fit_shared.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {

CollageProxy::CollageProxy(const PixelSet& target, double overlap_weight)
    : target_(target), pad_(std::max(target.width, target.height) / 2), overlap_weight_(overlap_weight) {
  distance_to_target_ = squared_distance_transform(pad_pixels(target, pad_));
  for (double& d : distance_to_target_) d = std::sqrt(d);
  for (int y = 0; y < target.height; ++y)
    for (int x = 0; x < target.width; ++x)
      if (target.cells[std::size_t(y) * target.width + x]) {
        target_cells_.push_back(static_cast<std::uint32_t>(y * target.width + x));
        for (float sy : {0.25f, 0.75f})
          for (float sx : {0.25f, 0.75f}) samples_.push_back({x + sx, y + sy});
      }
}

double CollageProxy::operator()(const std::vector<PixelMap>& maps, Scratch& s) const {
  const int W = target_.width + 2 * pad_, H = target_.height + 2 * pad_;
  s.stamp.assign(std::size_t(W) * H, 0);
  std::size_t cells = 0, overlap = 0;
  double outside = 0;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const PixelMap& m = maps[i];
    const auto mark = static_cast<std::uint16_t>(i + 1);
    for (const auto& p : samples_) {
      const double qx = m[0] * p[0] + m[1] * p[1] + m[2] + pad_, qy = m[3] * p[0] + m[4] * p[1] + m[5] + pad_;
      const int ix = static_cast<int>(std::clamp(qx, 0.0, W - 1.0)), iy = static_cast<int>(std::clamp(qy, 0.0, H - 1.0));
      auto& st = s.stamp[std::size_t(iy) * W + ix];
      if (st == mark) continue;
      if (st == 0) {
        ++cells;
        outside += distance_to_target_[std::size_t(iy) * W + ix];
      } else {
        ++overlap;
      }
      st = mark;
    }
  }
  // Mean distance of the collage to the target plus mean distance of the target to the collage.
  s.collage.width = target_.width;
  s.collage.height = target_.height;
  s.collage.cells.assign(std::size_t(target_.width) * target_.height, 0);
  for (int y = 0; y < target_.height; ++y)
    for (int x = 0; x < target_.width; ++x)
      s.collage.cells[std::size_t(y) * target_.width + x] = s.stamp[std::size_t(y + pad_) * W + x + pad_] != 0;
  const auto dt = squared_distance_transform(s.collage);
  double uncovered = 0;
  for (std::uint32_t c : target_cells_) uncovered += std::sqrt(dt[c]);
  const double n = static_cast<double>(target_cells_.size());
  if (!std::isfinite(uncovered)) uncovered = n * W;
  return outside / std::max<std::size_t>(cells, 1) + uncovered / n + overlap_weight_ * overlap / n;
}

double CollageProxy::copy_outside(const PixelMap& m) const {
  const int W = target_.width + 2 * pad_, H = target_.height + 2 * pad_;
  double sum = 0;
  for (const auto& p : samples_) {
    const double qx = m[0] * p[0] + m[1] * p[1] + m[2] + pad_, qy = m[3] * p[0] + m[4] * p[1] + m[5] + pad_;
    const int ix = static_cast<int>(std::clamp(qx, 0.0, W - 1.0)), iy = static_cast<int>(std::clamp(qy, 0.0, H - 1.0));
    sum += distance_to_target_[std::size_t(iy) * W + ix];
  }
  return sum / std::max<std::size_t>(samples_.size(), 1);
}

double chaos_iou(const std::vector<PixelMap>& maps, const std::vector<double>& probabilities, const PixelSet& target,
                 std::uint64_t seed, CollageProxy::Scratch& s) {
  const int w = target.width, h = target.height;
  s.hits.assign(std::size_t(w) * h, 0);
  const MapChain chain(probabilities);  // the one walker (a fitted system has no transitions)
  // Start at map 0's fixed point (on the attractor) when it has one.
  const PixelMap& m0 = maps[0];
  const double det = (1 - m0[0]) * (1 - m0[4]) - m0[1] * m0[3];
  double x = 0.5 * w, y = 0.5 * h;
  if (std::abs(det) > 1e-12) {
    x = ((1 - m0[4]) * m0[2] + m0[1] * m0[5]) / det;
    y = (m0[3] * m0[2] + (1 - m0[0]) * m0[5]) / det;
  }
  const std::uint64_t points = default_iterations(w, h, true, 0);
  Rng rng(seed, 0x10F);
  std::uint32_t state = chain.start(rng);
  std::uint64_t out = 0;
  for (std::uint64_t k = 0; k < points + 64; ++k) {
    const PixelMap& m = maps[state = chain.next(state, rng.next())];
    const double nx = m[0] * x + m[1] * y + m[2];
    y = m[3] * x + m[4] * y + m[5];
    x = nx;
    if (k < 64) continue;
    if (x >= 0 && y >= 0 && x < w && y < h) s.hits[std::size_t(y) * w + std::size_t(x)] = 1;
    else ++out;
  }
  return hits_iou(s.hits, target.cells, points, out);
}

}  // namespace ifsforge
