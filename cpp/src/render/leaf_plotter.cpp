#include "ifsforge/render/leaf_plotter.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ifsforge/core/cells.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/render/accumulator.h"
#include "ifsforge/render/recursion.h"

namespace ifsforge {

LeafPlotter::LeafPlotter(const Ifs& ifs, const Frame& frame)
    : frame_(frame), spatial_(ifs.spatial_dims()), channels_(ifs.dim() - ifs.spatial_dims()) {
  check_memory(static_cast<double>(frame.width()) * frame.height() *
                   (12.0 + (channels_ ? 8.0 + 12.0 * channels_ : 0.0) + (spatial_ == 3 ? 4.0 : 0.0)),
               "a " + std::to_string(frame.width()) + "x" + std::to_string(frame.height()) + " image of leaves");
  describe_channels(ifs, raster_);
  raster_.width = frame.width();
  raster_.height = frame.height();
  raster_.pixel_size = frame.pixel_size();
  const std::size_t pixels = std::size_t(frame.width()) * frame.height();
  mass_.assign(pixels, 0.0);
  weight_.assign(channels_ ? pixels : 0, 0.0);
  moments_.assign(pixels * channels_, 0.0);
  if (spatial_ == 3) raster_.depth.assign(pixels, -std::numeric_limits<float>::infinity());
}

void LeafPlotter::plot(Batch& batch, const Point& p, double mass) const {
  const auto px = frame_.to_pixel(p);
  if (!(px[0] >= 0.0 && px[0] < frame_.width() && px[1] >= 0.0 && px[1] < frame_.height())) return;
  batch.pixel.push_back(static_cast<std::uint32_t>(std::size_t(px[1]) * frame_.width() + std::size_t(px[0])));
  batch.mass.push_back(mass);
  if (spatial_ == 3) batch.depth.push_back(static_cast<float>(frame_.depth(p)));
  if (!channels_) return;
  const double weight = std::max(mass, std::numeric_limits<double>::min());
  batch.weight.push_back(weight);
  for (int c = 0; c < channels_; ++c) batch.moments.push_back(weight * p[spatial_ + c]);
}

template <typename Apply>
void LeafPlotter::spread(Batch& batch, Apply&& apply, const std::vector<Point>& points, double mass) const {
  constexpr int kMost = 16;
  std::uint32_t pixel[kMost];
  double weight[kMost], moments[kMost][kMaxDim];
  float depth[kMost];
  int count = 0;
  // An attractor point strictly inside a pixel puts positive measure there; one on a pixel's
  // edge (a shared corner of grid-aligned pieces) may belong to the neighbour: such points
  // count only when no point of the piece lies strictly inside a pixel.
  constexpr std::size_t kCached = 64;
  std::array<double, 2> cached[kCached];
  Point images[kCached];
  std::size_t inside = 0;
  const std::size_t cached_count = std::min(points.size(), kCached);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point p = apply(points[i]);
    const auto px = frame_.to_pixel(p);
    if (i < kCached) {
      images[i] = p;
      cached[i] = px;
    }
    inside += !on_cell_edge(px[0]) && !on_cell_edge(px[1]);
  }
  const double share = mass / static_cast<double>(inside ? inside : points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point p = i < cached_count ? images[i] : apply(points[i]);
    const auto px = i < cached_count ? cached[i] : frame_.to_pixel(p);
    if (inside && (on_cell_edge(px[0]) || on_cell_edge(px[1]))) continue;
    if (!(px[0] >= 0.0 && px[0] < frame_.width() && px[1] >= 0.0 && px[1] < frame_.height())) continue;
    const auto index = static_cast<std::uint32_t>(std::size_t(px[1]) * frame_.width() + std::size_t(px[0]));
    int k = 0;
    while (k < count && pixel[k] != index) ++k;
    if (k == count) {
      if (count == kMost) {  // not expected for a piece smaller than a pixel: plot it apart
        plot(batch, p, share);
        continue;
      }
      pixel[k] = index;
      weight[k] = 0.0;
      depth[k] = -std::numeric_limits<float>::infinity();
      std::fill(moments[k], moments[k] + channels_, 0.0);
      ++count;
    }
    weight[k] += share;
    if (spatial_ == 3) depth[k] = std::max(depth[k], static_cast<float>(frame_.depth(p)));
    for (int c = 0; c < channels_; ++c) moments[k][c] += share * p[spatial_ + c];
  }
  for (int k = 0; k < count; ++k) {
    batch.pixel.push_back(pixel[k]);
    batch.mass.push_back(weight[k]);
    if (spatial_ == 3) batch.depth.push_back(depth[k]);
    if (!channels_) continue;
    const double w = std::max(weight[k], std::numeric_limits<double>::min());
    batch.weight.push_back(w);
    for (int c = 0; c < channels_; ++c) batch.moments.push_back(moments[k][c] / std::max(weight[k], 1e-300) * w);
  }
}

void LeafPlotter::plot_spread(Batch& batch, const double* m, const std::vector<Point>& points, double mass) const {
  const int n = spatial_ + channels_;
  spread(batch, [&](const Point& p) { return composed::apply(m, n, p); }, points, mass);
}

void LeafPlotter::plot_spread(Batch& batch, const AffineMap& m, const std::vector<Point>& points, double mass) const {
  spread(batch, [&](const Point& p) { return m(p); }, points, mass);
}

void LeafPlotter::add(Batch& batch, std::uint32_t pixel, double mass, const double* moments) const {
  batch.pixel.push_back(pixel);
  batch.mass.push_back(mass);
  if (!channels_) return;
  batch.weight.push_back(mass);
  for (int c = 0; c < channels_; ++c) batch.moments.push_back(moments[c]);
}

void LeafPlotter::apply(const Batch& batch) {
  for (std::size_t k = 0; k < batch.pixel.size(); ++k) {
    const std::uint32_t p = batch.pixel[k];
    mass_[p] += batch.mass[k];
    if (!batch.depth.empty()) raster_.depth[p] = std::max(raster_.depth[p], batch.depth[k]);
    if (!channels_) continue;
    weight_[p] += batch.weight[k];
    for (int c = 0; c < channels_; ++c) moments_[std::size_t(p) * channels_ + c] += batch.moments[k * channels_ + c];
  }
  raster_.points += batch.pixel.size();
}

void LeafPlotter::submit(std::uint64_t job, Batch&& batch) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (job != next_job_) {
    waiting_.emplace(job, std::move(batch));
    return;
  }
  apply(batch);
  ++next_job_;
  for (auto it = waiting_.find(next_job_); it != waiting_.end(); it = waiting_.find(next_job_)) {
    apply(it->second);
    waiting_.erase(it);
    ++next_job_;
  }
}

Raster LeafPlotter::finish() {
  const std::size_t pixels = mass_.size();
  raster_.density.assign(pixels, 0.0f);
  raster_.channels.assign(pixels * channels_, 0.0f);
  constexpr float kCovered = std::numeric_limits<float>::denorm_min();
  for (std::size_t p = 0; p < pixels; ++p) {
    const bool covered = mass_[p] > 0.0 || (channels_ && weight_[p] > 0.0) ||
                         (!raster_.depth.empty() && std::isfinite(raster_.depth[p]));
    if (!covered) continue;
    raster_.density[p] = std::max(static_cast<float>(mass_[p]), kCovered);
    for (int c = 0; c < channels_ && weight_[p] > 0.0; ++c)
      raster_.channels[p * channels_ + c] = static_cast<float>(moments_[p * channels_ + c] / weight_[p]);
  }
  return std::move(raster_);
}

namespace composed {

void identity(int n, double* m) {
  std::fill(m, m + size(n), 0.0);
  for (int r = 0; r < n; ++r) m[r * n + r] = 1.0;
}

void after(const AffineMap& outer, const double* inner, int n, double* out) {
  const double* ib = inner + n * n;
  for (int r = 0; r < n; ++r) {
    double offset = outer.b(r);
    for (int k = 0; k < n; ++k) offset += outer.a(r, k) * ib[k];
    out[n * n + r] = offset;
    for (int c = 0; c < n; ++c) {
      double v = 0.0;
      for (int k = 0; k < n; ++k) v += outer.a(r, k) * inner[k * n + c];
      out[r * n + c] = v;
    }
  }
}

void before(const double* outer, const AffineMap& inner, int n, double* out) {
  const double* ob = outer + n * n;
  for (int r = 0; r < n; ++r) {
    double offset = ob[r];
    for (int k = 0; k < n; ++k) offset += outer[r * n + k] * inner.b(k);
    out[n * n + r] = offset;
    for (int c = 0; c < n; ++c) {
      double v = 0.0;
      for (int k = 0; k < n; ++k) v += outer[r * n + k] * inner.a(k, c);
      out[r * n + c] = v;
    }
  }
}

Point apply(const double* m, int n, const Point& p) {
  Point q{};
  for (int r = 0; r < n; ++r) {
    double v = m[n * n + r];
    for (int c = 0; c < n; ++c) v += m[r * n + c] * p[c];
    q[r] = v;
  }
  return q;
}

}  // namespace composed

PieceBoxes::PieceBoxes(const Ifs& ifs, const Frame& frame)
    : frame_(frame), n_(ifs.dim()), spatial_(ifs.spatial_dims()) {
  piece_box(ifs, ifs.attractor_bounds(1u << 16), kPieceBoxMargin, false, center_, half_);
}

void PieceBoxes::pixel_box(const double* m, double* lo, double* hi) const {
  Point center{};
  double half[3] = {0, 0, 0};
  for (int r = 0; r < spatial_; ++r) {
    double c = m[n_ * n_ + r], h = 0.0;
    for (int k = 0; k < n_; ++k) {
      c += m[r * n_ + k] * center_[k];
      h += std::abs(m[r * n_ + k]) * half_[k];
    }
    center[r] = c;
    half[r] = h;
  }
  const auto px = frame_.to_pixel(center);
  const auto& projection = frame_.projection();
  for (int axis = 0; axis < 2; ++axis) {
    double extent = 0.0;
    for (int k = 0; k < spatial_; ++k) extent += std::abs(projection[axis][k]) * half[k];
    extent /= frame_.pixel_size();
    lo[axis] = px[axis] - extent;
    hi[axis] = px[axis] + extent;
  }
}

Point PieceBoxes::center() const {
  Point c{};
  std::copy(center_.begin(), center_.end(), c.begin());
  return c;
}

PieceFit PieceBoxes::fit(const double* m) const {
  double lo[2], hi[2];
  pixel_box(m, lo, hi);
  if (hi[0] < 0.0 || lo[0] >= frame_.width() || hi[1] < 0.0 || lo[1] >= frame_.height()) return PieceFit::Off;
  if (in_one_cell(lo, hi, 2)) return PieceFit::OnePixel;
  if (std::max(hi[0] - lo[0], hi[1] - lo[1]) < 1.0) return PieceFit::Small;
  return PieceFit::Split;
}

std::vector<Point> spread_points(const Ifs& ifs) {
  std::vector<Point> points;
  for (const Point& p : ifs.fixed_points()) {
    bool finite = true;
    for (int c = 0; c < ifs.dim(); ++c) finite &= std::isfinite(p[c]);
    if (finite) points.push_back(p);
  }
  if (points.empty()) points.push_back(ifs.start_point());
  // Their images under the maps, a level or two (W^d of the fixed points, about 16 points).
  while (points.size() * ifs.size() <= 24) {
    std::vector<Point> next = points;
    for (const Point& p : points)
      for (const AffineMap& m : ifs.maps()) next.push_back(m(p));
    points.swap(next);
  }
  const int k = ifs.spatial_dims();
  std::vector<Point> extremes(2 * k, ifs.start_point());
  sample_attractor(ifs, 1u << 14, 0x5E7D, [&](const Point& p) {
    for (int axis = 0; axis < k; ++axis) {
      if (p[axis] < extremes[2 * axis][axis]) extremes[2 * axis] = p;
      if (p[axis] > extremes[2 * axis + 1][axis]) extremes[2 * axis + 1] = p;
    }
  });
  points.insert(points.end(), extremes.begin(), extremes.end());
  return points;
}

}  // namespace ifsforge
