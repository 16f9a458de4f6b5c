#include "ifsforge/render/point_recursive.h"

#include <algorithm>
#include <limits>
#include <map>
#include <mutex>

#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/accumulator.h"
#include "ifsforge/render/recursion.h"

namespace ifsforge {
namespace {

/// The leaves of one job that land on the image.
struct LeafList {
  std::vector<std::uint32_t> pixel;
  std::vector<double> mass;
  std::vector<float> channels;  // pixel-major
};

}  // namespace

Raster PointRecursive::render(const Ifs& ifs, const RenderOptions& options) const {
  ifs.require_attractor();
  const Frame frame = Frame::fit(ifs, options.width, options.height, options.window, options.view);
  const int fallback = default_depth(ifs.size(), frame.width(), frame.height());
  const RecursionPlan plan = plan_recursion(ifs, options.depth, 0.5 * frame.pixel_size(), fallback);
  const std::size_t pixels = std::size_t(frame.width()) * frame.height();
  const int channels = ifs.dim() - ifs.spatial_dims();
  check_memory(pixels * (4.0 + 12.0 * channels + (channels ? 4.0 : 0.0)),
               "a " + std::to_string(frame.width()) + "x" + std::to_string(frame.height()) +
                   " point-recursive image");

  Raster raster;
  describe_channels(ifs, raster);
  raster.width = frame.width();
  raster.height = frame.height();
  // Density accumulates in single precision straight into the raster; a covered pixel is
  // kept above 0 even when its mass underflows.
  raster.density.assign(pixels, 0.0f);
  std::vector<std::uint32_t> hits(channels ? pixels : 0, 0u);
  std::vector<double> sums(pixels * channels, 0.0);
  constexpr float kCovered = std::numeric_limits<float>::denorm_min();

  // Results are applied strictly in job (address) order: floating-point sums come out the
  // same for any number of threads.
  std::mutex mutex;
  std::map<std::uint64_t, LeafList> waiting;
  std::uint64_t next_job = 0;
  auto apply = [&](const LeafList& list) {
    for (std::size_t k = 0; k < list.pixel.size(); ++k) {
      const std::uint32_t px = list.pixel[k];
      raster.density[px] = std::max(raster.density[px] + static_cast<float>(list.mass[k]), kCovered);
      if (!channels) continue;
      ++hits[px];
      for (int c = 0; c < channels; ++c) sums[std::size_t(px) * channels + c] += list.channels[k * channels + c];
    }
    raster.points += list.pixel.size();
  };

  const Point start = ifs.start_point();
  const int spatial = ifs.spatial_dims();
  const double w = frame.width(), h = frame.height();
  parallel_jobs(
      plan.jobs, options.threads,
      [&](std::size_t job, int) {
        LeafList list;
        walk_job(ifs, plan, start, job, [&](const Point& p, double m, const std::uint32_t*, int) {
          const auto px = frame.to_pixel(p);
          if (!(px[0] >= 0.0 && px[0] < w && px[1] >= 0.0 && px[1] < h)) return;
          list.pixel.push_back(static_cast<std::uint32_t>(std::size_t(px[1]) * frame.width() + std::size_t(px[0])));
          list.mass.push_back(m);
          for (int c = 0; c < channels; ++c) list.channels.push_back(static_cast<float>(p[spatial + c]));
        });
        std::lock_guard<std::mutex> lock(mutex);
        if (job != next_job) {
          waiting.emplace(job, std::move(list));
          return;
        }
        apply(list);
        ++next_job;
        for (auto it = waiting.find(next_job); it != waiting.end(); it = waiting.find(next_job)) {
          apply(it->second);
          waiting.erase(it);
          ++next_job;
        }
      },
      options.progress);

  raster.channels.assign(pixels * channels, 0.0f);
  for (std::size_t i = 0; channels && i < pixels; ++i)
    for (int c = 0; c < channels && hits[i]; ++c)
      raster.channels[i * channels + c] = static_cast<float>(sums[i * channels + c] / hits[i]);
  return raster;
}

}  // namespace ifsforge
