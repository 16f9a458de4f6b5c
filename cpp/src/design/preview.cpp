#include "ifsforge/design/preview.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/model/capabilities.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/render/tone_map.h"

namespace ifsforge {
namespace {

// Fixed job size: the job count, and so the cloud, depends only on `count`.
constexpr std::size_t kJobPoints = 1 << 16;
constexpr int kWarmUp = 100;  // iterations that bring a job's orbit onto the attractor
constexpr std::size_t kQuantileSamples = 1 << 15;  // points behind the bounds of non-hyperbolic systems

// Channels the colour comes from: the colour group, and a separate alpha channel if any.
struct ColorChannels {
  ColorModel model = ColorModel::None;
  int first = -1;  // first colour channel
  int count = 0;   // 1 (gray), 3 (rgb, hsi) or 4 (rgba)
  int alpha = -1;  // alpha channel outside the colour group
};

ColorChannels color_channels(const ChannelLayout& layout) {
  ColorChannels c;
  c.model = layout.color_model();
  c.first = layout.color_index();
  c.count = c.model == ColorModel::Gray ? 1 : c.model == ColorModel::Rgba ? 4 : c.model == ColorModel::None ? 0 : 3;
  if (c.model != ColorModel::Rgba) c.alpha = layout.alpha_index();
  return c;
}

void box_edges(int spatial, std::vector<std::pair<int, int>>& edges) {
  // Corners are numbered by bits (bit d set: the high end along axis d); an edge joins
  // corners that differ in one bit.
  const int corners = 1 << spatial;
  for (int a = 0; a < corners; ++a)
    for (int d = 0; d < spatial; ++d)
      if (!(a & (1 << d))) edges.emplace_back(a, a | (1 << d));
}


// What every job shares: the system, its sampler, the start point, the seed, the size.
struct PreviewOrbit {
  const Ifs& ifs;
  MapChain chain;  // the one walker's choice of maps (a recurrent system's transitions)
  Point start;
  std::uint64_t seed;
  std::size_t count;
};

// Where a job writes: the cloud's arrays and its own bounds.
struct Sink {
  float* positions;
  float* channels;
  std::uint32_t* pieces;
  Bounds* bounds;
};

/// One job of random iteration (5.1.1) in dimension N (a compile-time constant, so the map
/// application unrolls): stream `job` of the seed, kWarmUp steps onto the attractor, then
/// points [job * kJobPoints, ...) with their piece and the job's bounds.
template <int N>
void iterate(const PreviewOrbit& orbit, int spatial, std::size_t job, const Sink& sink) {
  const Ifs& ifs = orbit.ifs;
  const std::size_t maps = ifs.size();
  std::vector<double> a(maps * N * N), b(maps * N);
  for (std::size_t i = 0; i < maps; ++i)
    for (int r = 0; r < N; ++r) {
      for (int c = 0; c < N; ++c) a[(i * N + r) * N + c] = ifs.map(i).a(r, c);
      b[i * N + r] = ifs.map(i).b(r);
    }
  Rng rng(orbit.seed, job);
  double p[N], q[N];
  std::copy_n(orbit.start.begin(), N, p);
  auto step = [&](std::uint32_t i) {
    const double* m = &a[i * N * N];
    for (int r = 0; r < N; ++r) {
      double v = b[i * N + r];
      for (int c = 0; c < N; ++c) v += m[r * N + c] * p[c];
      q[r] = v;
    }
    std::copy_n(q, N, p);
  };
  std::uint32_t i = orbit.chain.start(rng);
  for (int k = 0; k < kWarmUp; ++k) step(i = orbit.chain.next(i, rng.next()));
  double lo[N], hi[N];
  std::fill_n(lo, N, std::numeric_limits<double>::infinity());
  std::fill_n(hi, N, -std::numeric_limits<double>::infinity());
  const int extra = N - spatial;
  const std::size_t end = std::min(orbit.count, (job + 1) * kJobPoints);
  for (std::size_t k = job * kJobPoints; k < end; ++k) {
    step(i = orbit.chain.next(i, rng.next()));
    double sum = 0.0;
    for (int c = 0; c < N; ++c) sum += p[c];
    if (sum - sum != 0.0)  // an infinite or NaN coordinate
      throw DivergentSystemError("system '" + ifs.name() + "' escapes to infinity under iteration");
    for (int c = 0; c < N; ++c) {
      lo[c] = std::min(lo[c], p[c]);
      hi[c] = std::max(hi[c], p[c]);
    }
    for (int c = 0; c < spatial; ++c) sink.positions[k * 3 + c] = static_cast<float>(p[c]);
    for (int c = 0; c < extra; ++c) sink.channels[k * extra + c] = static_cast<float>(p[spatial + c]);
    sink.pieces[k] = i;
  }
  sink.bounds->lo.assign(lo, lo + N);
  sink.bounds->hi.assign(hi, hi + N);
}

}  // namespace

void piece_color(std::size_t index, bool dim, float* rgba) {
  // Golden-angle hue steps keep consecutive maps far apart on the colour wheel.
  const double hue = std::fmod(0.08 + 0.6180339887498949 * static_cast<double>(index), 1.0);
  const double h6 = hue * 6.0, f = h6 - std::floor(h6);
  const double v = dim ? 0.45 : 1.0, s = 0.7;
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r, g, b;
  switch (static_cast<int>(h6) % 6) {
    case 0: r = v; g = t; b = p; break;
    case 1: r = q; g = v; b = p; break;
    case 2: r = p; g = v; b = t; break;
    case 3: r = p; g = q; b = v; break;
    case 4: r = t; g = p; b = v; break;
    default: r = v; g = p; b = q; break;
  }
  rgba[0] = static_cast<float>(r);
  rgba[1] = static_cast<float>(g);
  rgba[2] = static_cast<float>(b);
  rgba[3] = 1.0f;
}

PreviewCloud preview_cloud(const Ifs& ifs, const PreviewOptions& options) {
  require_sampler_handles("preview_cloud", ifs);
  ifs.require_attractor();
  if (options.count == 0) throw InputError("a preview needs at least one point");
  const int n = ifs.dim(), spatial = ifs.spatial_dims(), extra = n - spatial;
  const std::size_t count = options.count;
  const bool hyperbolic = ifs.classify() == Classification::Hyperbolic;
  check_memory(static_cast<double>(count) * (3 + 4 + extra) * sizeof(float) + count * sizeof(std::uint32_t) +
                   (hyperbolic ? 0.0 : count * sizeof(double)),
               "a preview of " + std::to_string(count) + " points");

  PreviewCloud cloud;
  cloud.count = count;
  cloud.positions.assign(count * 3, 0.0f);
  cloud.pieces.resize(count);
  std::vector<float> channels(count * extra);
  const std::size_t jobs = (count + kJobPoints - 1) / kJobPoints;
  std::vector<Bounds> job_bounds(jobs);
  const PreviewOrbit orbit{ifs, MapChain(ifs), ifs.start_point(), options.seed, count};
  parallel_jobs(jobs, options.threads, [&](std::size_t job, int) {
    Sink sink{cloud.positions.data(), channels.data(), cloud.pieces.data(), &job_bounds[job]};
    switch (n) {
      case 2: iterate<2>(orbit, spatial, job, sink); break;
      case 3: iterate<3>(orbit, spatial, job, sink); break;
      case 4: iterate<4>(orbit, spatial, job, sink); break;
      case 5: iterate<5>(orbit, spatial, job, sink); break;
      case 6: iterate<6>(orbit, spatial, job, sink); break;
      case 7: iterate<7>(orbit, spatial, job, sink); break;
      default: iterate<8>(orbit, spatial, job, sink); break;
    }
  });

  // Bounds per channel, as Ifs::attractor_bounds takes them: the extremes of a hyperbolic
  // attractor (min/max merge exactly, whatever the job order), the bulk (0.1% / 99.9%
  // quantiles) of a measure whose support may be unbounded.
  auto value = [&](std::size_t k, int c) {
    return c < spatial ? static_cast<double>(cloud.positions[k * 3 + c]) : static_cast<double>(channels[k * extra + c - spatial]);
  };
  cloud.bounds = job_bounds[0];
  for (std::size_t j = 1; j < jobs; ++j)
    for (int c = 0; c < n; ++c) {
      cloud.bounds.lo[c] = std::min(cloud.bounds.lo[c], job_bounds[j].lo[c]);
      cloud.bounds.hi[c] = std::max(cloud.bounds.hi[c], job_bounds[j].hi[c]);
    }
  if (!hyperbolic) {
    // Quantiles from an evenly strided subsample: a preview's box needs no more precision,
    // and n_channels selections over every point would cost more than the iteration.
    const std::size_t stride = std::max<std::size_t>(1, count / kQuantileSamples);
    std::vector<double> column;
    column.reserve(count / stride + 1);
    for (int c = 0; c < n; ++c) {
      column.clear();
      for (std::size_t k = 0; k < count; k += stride) column.push_back(value(k, c));
      cloud.bounds.lo[c] = quantile(column, 0.001);
      cloud.bounds.hi[c] = quantile(column, 0.999);
    }
  }

  const ColorChannels cc = color_channels(ifs.layout());
  cloud.coloring = options.coloring;
  if (cloud.coloring == PreviewColoring::Auto)
    cloud.coloring = cc.model == ColorModel::None ? PreviewColoring::Pieces : PreviewColoring::Channels;
  if (cloud.coloring == PreviewColoring::Channels && cc.model == ColorModel::None)
    throw InputError("layout '" + ifs.layout().text() + "' has no color channels to color the preview with");

  cloud.colors.resize(count * 4);
  if (cloud.coloring == PreviewColoring::Pieces) {
    std::vector<float> palette(ifs.size() * 4);
    for (std::size_t i = 0; i < ifs.size(); ++i)
      piece_color(i, options.highlight >= 0 && static_cast<std::size_t>(options.highlight) != i, &palette[i * 4]);
    for (std::size_t k = 0; k < count; ++k) std::copy_n(&palette[cloud.pieces[k] * 4], 4, &cloud.colors[k * 4]);
  } else {
    // Values already in [0, 1] are shown as they are; otherwise Eq. 101 maps each channel's
    // range onto [0, 1] (as the renderers' tone mapping does).
    std::vector<int> used;
    for (int c = 0; c < cc.count; ++c) used.push_back(cc.first + c);
    if (cc.alpha >= 0) used.push_back(cc.alpha);
    bool unit = true;
    for (int c : used) unit = unit && cloud.bounds.lo[c] >= 0.0 && cloud.bounds.hi[c] <= 1.0;
    std::vector<double> lo(n, 0.0), scale(n, 1.0);
    if (!unit)
      for (int c : used) {
        const double range = cloud.bounds.hi[c] - cloud.bounds.lo[c];
        lo[c] = range > 0 ? cloud.bounds.lo[c] : cloud.bounds.lo[c] - 0.5;
        scale[c] = range > 0 ? 1.0 / range : 1.0;
      }
    auto normalised = [&](std::size_t k, int c) { return std::clamp((value(k, c) - lo[c]) * scale[c], 0.0, 1.0); };
    for (std::size_t k = 0; k < count; ++k) {
      float* px = &cloud.colors[k * 4];
      if (cc.model == ColorModel::Hsi) {
        hsi_to_rgb(normalised(k, cc.first), normalised(k, cc.first + 1), normalised(k, cc.first + 2), px);
      } else if (cc.model == ColorModel::Gray) {
        px[0] = px[1] = px[2] = static_cast<float>(normalised(k, cc.first));
      } else {
        for (int c = 0; c < 3; ++c) px[c] = static_cast<float>(normalised(k, cc.first + c));
      }
      px[3] = cc.model == ColorModel::Rgba ? static_cast<float>(normalised(k, cc.first + 3))
              : cc.alpha >= 0              ? static_cast<float>(normalised(k, cc.alpha))
                                           : 1.0f;
    }
  }

  // Collage frames: the bounding box B of the cloud and its image w_i(B) under every map
  // (the extra channels held at the middle of their range, which matters only when they
  // feed back into the position).
  std::vector<std::pair<int, int>> edges;
  box_edges(spatial, edges);
  const int corners = 1 << spatial;
  std::vector<Point> corner(corners);
  for (int a = 0; a < corners; ++a) {
    Point& p = corner[a];
    p.fill(0.0);
    for (int c = 0; c < n; ++c)
      p[c] = c < spatial ? ((a >> c) & 1 ? cloud.bounds.hi[c] : cloud.bounds.lo[c])
                         : 0.5 * (cloud.bounds.lo[c] + cloud.bounds.hi[c]);
  }
  auto add_frame = [&](const std::vector<Point>& points, std::uint32_t piece, const float* rgba) {
    for (const auto& [a, b] : edges)
      for (int end : {a, b}) {
        for (int c = 0; c < 3; ++c) cloud.frame_positions.push_back(c < spatial ? static_cast<float>(points[end][c]) : 0.0f);
        cloud.frame_colors.insert(cloud.frame_colors.end(), rgba, rgba + 4);
        cloud.frame_pieces.push_back(piece);
      }
  };
  const float gray[4] = {0.6f, 0.6f, 0.6f, 1.0f};
  add_frame(corner, static_cast<std::uint32_t>(ifs.size()), gray);
  std::vector<Point> image(corners);
  for (std::size_t i = 0; i < ifs.size(); ++i) {
    for (int a = 0; a < corners; ++a) image[a] = ifs.map(i)(corner[a]);
    float rgba[4];
    piece_color(i, options.highlight >= 0 && static_cast<std::size_t>(options.highlight) != i, rgba);
    add_frame(image, static_cast<std::uint32_t>(i), rgba);
  }
  return cloud;
}

}  // namespace ifsforge
