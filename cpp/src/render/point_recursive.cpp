#include "ifsforge/render/point_recursive.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>

#include "ifsforge/core/cells.h"
#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/accumulator.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/recursion.h"

namespace ifsforge {
namespace {

/// The leaves of one job that land on the image.
struct LeafList {
  std::vector<std::uint32_t> pixel;
  std::vector<double> mass;
  std::vector<float> channels;  // pixel-major
  std::vector<float> depth;     // 3D systems

  void clear() {
    pixel.clear();
    mass.clear();
    channels.clear();
    depth.clear();
  }
};

/// Thrown by a job that exceeds its node budget: render() falls back to the Eq. 59 depth.
struct OverBudget {};

}  // namespace

Raster PointRecursive::render(const Ifs& ifs, const RenderOptions& options) const {
  // The address tree knows neither the transitions' forbidden words nor the set C of w_0.
  if (ifs.recurrent())
    throw InputError("point recursive rendering does not follow transitions: render recurrent system '" +
                     ifs.name() + "' with chaos, probabilistic-domain or photocopy");
  if (!ifs.condensation().empty())
    throw InputError("point recursive rendering has no condensation set: render '" + ifs.name() +
                     "' with dia, mpa or self-congruent");
  ifs.require_attractor();
  const Frame frame = Frame::fit(ifs, options.width, options.height, options.window, options.view);
  const int eq59 = default_depth(ifs.size(), frame.width(), frame.height());
  RecursionPlan plan = plan_recursion(ifs, options.depth, eq59);
  if (options.depth <= 0) plan.max_depth = depth_for_size(ifs, plan, frame.pixel_size(), 2, eq59);
  const bool fit_pixels = options.depth <= 0;
  // Pixels: a piece smaller than this is not split further. Coverage needs only the pixels a
  // piece touches; the measure needs the share of each, so straddling pieces split to an
  // eighth of a pixel (L1 error about 0.02 against a long chaos game, the README says).
  // Pixels: a piece smaller than this is not split further (straddling pieces spread their
  // mass, see below). 1 is enough for coverage; the measure's share of each pixel sharpens
  // as the cut shrinks (1/8: L1 about 0.02 from a long chaos game, for several times the work).
  const double cut = ParameterValues(*this, options).number("cut", 1.0 / 64.0, 1.0);
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
  assign_large(raster.density, pixels, 0.0f);
  raster.pixel_size = frame.pixel_size();
  if (ifs.spatial_dims() == 3) assign_large(raster.depth, pixels, -std::numeric_limits<float>::infinity());
  std::vector<std::uint32_t> hits;
  std::vector<double> sums;
  assign_large(hits, channels ? pixels : 0, 0u);
  assign_large(sums, pixels * channels, 0.0);
  constexpr float kCovered = std::numeric_limits<float>::denorm_min();

  // Results are applied strictly in job (address) order: floating-point sums come out the
  // same for any number of threads.
  std::mutex mutex;
  std::map<std::uint64_t, LeafList> waiting;
  // Applied lists keep their buffers for later jobs: growing a fresh list page by page for
  // every job cost more page faults and copies than the plotting itself.
  std::vector<LeafList> spare;
  std::uint64_t next_job = 0;
  auto apply = [&](const LeafList& list) {
    for (std::size_t k = 0; k < list.pixel.size(); ++k) {
      const std::uint32_t px = list.pixel[k];
      raster.density[px] = std::max(raster.density[px] + static_cast<float>(list.mass[k]), kCovered);
      if (!list.depth.empty()) raster.depth[px] = std::max(raster.depth[px], list.depth[k]);
      if (!channels) continue;
      ++hits[px];
      for (int c = 0; c < channels; ++c) sums[std::size_t(px) * channels + c] += list.channels[k * channels + c];
    }
    raster.points += list.pixel.size();
  };

  const Point start = ifs.start_point();
  const Point center = box_center(plan);  // leaves plot at the centre of their piece's box
  // Representatives of a piece too small to split further but straddling pixels: the images
  // under the words u of length d of a few points (at most 16 images, same as d more levels
  // without box tests), each carrying the share p_u of the piece's mass. For coverage
  // (binary) the points are the fixed points, so every image lies on the attractor and the
  // pixels the piece touches are all plotted. For the measure they are the centre of the box
  // B, so each image is the centre of the sub-piece's box w_u(B): never a point on a pixel
  // edge that the sub-piece only touches.
  std::vector<Point> spread;
  if (options.binary) {
    for (const Point& p : ifs.fixed_points())
      if (std::isfinite(p[0])) spread.push_back(p);
  } else {
    spread.push_back(center);
  }
  if (spread.empty()) spread.push_back(start);
  std::vector<double> spread_share(spread.size(), 1.0 / static_cast<double>(spread.size()));
  while (spread.size() * ifs.size() <= 16) {
    std::vector<Point> next;
    std::vector<double> next_share;
    for (std::size_t k = 0; k < spread.size(); ++k)
      for (std::size_t i = 0; i < ifs.size(); ++i) {
        next.push_back(ifs.map(i)(spread[k]));
        next_share.push_back(spread_share[k] * ifs.probabilities()[i]);
      }
    spread.swap(next);
    spread_share.swap(next_share);
  }
  const int spatial = ifs.spatial_dims();
  const double w = frame.width(), h = frame.height();
  auto pixel_box = [&](const AffineMap& m, double* lo, double* hi) { piece_pixel_box(frame, plan, m, lo, hi); };
  // Pieces that stay wider than a pixel in one direction while thinning in the other (a rough
  // fractal interpolation graph) would split for ever: each job has a node budget, checked per
  // job so that the outcome does not depend on the thread count.
  // 128 nodes per pixel (at least 2^24 in all) is several times what a hyperbolic system needs.
  const std::uint64_t total = std::max<std::uint64_t>(std::uint64_t(1) << 24, 128 * std::uint64_t(pixels));
  const std::uint64_t budget = fit_pixels ? std::max<std::uint64_t>(1u << 12, total / plan.jobs) : 0;
  auto stop = [&](const RecursionNode& node) {
    double lo[2], hi[2];
    pixel_box(node.map, lo, hi);
    if (hi[0] < 0.0 || lo[0] >= w || hi[1] < 0.0 || lo[1] >= h) return true;  // misses the image
    if (!fit_pixels) return false;
    if (in_one_cell(lo, hi, 2)) return true;
    return std::max(hi[0] - lo[0], hi[1] - lo[1]) < cut;
  };
  try {
    parallel_jobs(
        plan.jobs, options.threads,
        [&](std::size_t job, int) {
          LeafList list;
          {
            std::lock_guard<std::mutex> lock(mutex);
            if (!spare.empty()) {
              list = std::move(spare.back());
              spare.pop_back();
            }
          }
          auto plot = [&](const Point& p, double mass) {
            const auto px = frame.to_pixel(p);
            if (!(px[0] >= 0.0 && px[0] < w && px[1] >= 0.0 && px[1] < h)) return;
            list.pixel.push_back(static_cast<std::uint32_t>(std::size_t(px[1]) * frame.width() + std::size_t(px[0])));
            list.mass.push_back(mass);
            if (spatial == 3) list.depth.push_back(static_cast<float>(frame.depth(p)));
            for (int c = 0; c < channels; ++c) list.channels.push_back(static_cast<float>(p[spatial + c]));
          };
          std::vector<Point> images(spread.size());
          std::vector<char> strictly(spread.size());
          std::uint64_t nodes = 0;
          auto counted_stop = [&](const RecursionNode& node) {
            if (budget && ++nodes > budget) throw OverBudget{};
            return stop(node);
          };
          walk_job(ifs, plan, job, counted_stop, [&](const RecursionNode& node) {
            double lo[2], hi[2];
            if (fit_pixels) pixel_box(node.map, lo, hi);
            if (!fit_pixels || in_one_cell(lo, hi, 2)) {
              plot(node.map(center), node.mass);
              return;
            }
            // Only the images strictly inside a pixel (a point on a pixel edge belongs to
            // neither side), as LeafPlotter::plot_spread does; their shares carry all the mass.
            double inside = 0.0;
            for (std::size_t k = 0; k < spread.size(); ++k) {
              images[k] = node.map(spread[k]);
              const auto px = frame.to_pixel(images[k]);
              strictly[k] = !on_cell_edge(px[0]) && !on_cell_edge(px[1]);
              if (strictly[k]) inside += spread_share[k];
            }
            for (std::size_t k = 0; k < spread.size(); ++k)
              if (inside == 0.0 || strictly[k])
                plot(images[k], node.mass * spread_share[k] / (inside == 0.0 ? 1.0 : inside));
          });
          std::lock_guard<std::mutex> lock(mutex);
          if (job != next_job) {
            waiting.emplace(job, std::move(list));
            return;
          }
          apply(list);
          list.clear();
          spare.push_back(std::move(list));
          ++next_job;
          for (auto it = waiting.find(next_job); it != waiting.end(); it = waiting.find(next_job)) {
            apply(it->second);
            it->second.clear();
            spare.push_back(std::move(it->second));
            waiting.erase(it);
            ++next_job;
          }
        },
        options.progress);
  } catch (const OverBudget&) {
    // The pixel-size stop would split for ever (or nearly): the seed's PRR at Eq. 59's depth
    // (N^L >= H V leaves) ends every branch, whatever the system.
    RenderOptions fixed = options;
    fixed.depth = eq59;
    return render(ifs, fixed);
  }

  assign_large(raster.channels, pixels * channels, 0.0f);
  for (std::size_t i = 0; channels && i < pixels; ++i)
    for (int c = 0; c < channels && hits[i]; ++c)
      raster.channels[i * channels + c] = static_cast<float>(sums[i * channels + c] / hits[i]);
  return raster;
}

}  // namespace ifsforge
