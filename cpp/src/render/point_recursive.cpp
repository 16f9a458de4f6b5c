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
#include "point_recursive_leaves.h"
#include "polar_render.h"

namespace ifsforge {
namespace {

using prr::decode_leaves;
using prr::encode_leaves;
using prr::JobCoverage;
using prr::LeafList;
using prr::NodeCounts;
using prr::OverBudget;
using prr::PixelSums;

/// What every job of one render shares, and one job's walk.
struct PrrImage {
  const Ifs& ifs;
  Frame frame;
  int eq59 = 0;
  RecursionPlan plan;
  bool fit_pixels = false;
  bool binary = false;
  double cut = 1.0;
  int channels = 0, spatial = 2;
  Point center{};
  // Representatives of a piece too small to split further but straddling pixels: the images
  // under the words u of length d of a few points (at most 16 images, same as d more levels
  // without box tests), each carrying the share p_u of the piece's mass. For coverage
  // (binary) the points are the fixed points, so every image lies on the attractor and the
  // pixels the piece touches are all plotted. For the measure they are the centre of the box
  // B, so each image is the centre of the sub-piece's box w_u(B): never a point on a pixel
  // edge that the sub-piece only touches.
  std::vector<Point> spread;
  std::vector<double> spread_share;
  std::vector<double> spread_by_coordinate;  // coordinate c of spread[k] at [c * spread.size() + k]
  std::uint64_t budget = 0;  // nodes per group (0: no budget, at a fixed depth)
  std::uint64_t groups = 1;  // N^prefix address prefixes of the uniform plan

  PrrImage(const Ifs& system, const RenderOptions& options, const Renderer& renderer)
      : ifs(system),
        frame(Frame::fit(system, options.width, options.height, options.window, options.view, Frame::kMargin,
                         resolve_threads(options.threads))) {
    // The address tree knows neither the transitions' forbidden words nor the set C of w_0:
    // capabilities() leaves them out, so render() refuses them before this.
    ifs.require_attractor();
    eq59 = default_depth(ifs.size(), frame.width(), frame.height());
    plan = plan_recursion(ifs, options.depth, eq59, resolve_threads(options.threads));
    if (options.depth <= 0) plan.max_depth = depth_for_size(ifs, plan, frame.pixel_size(), 2, eq59);
    fit_pixels = options.depth <= 0;
    binary = options.binary;
    // Pixels: a piece smaller than this is not split further (straddling pieces spread their
    // mass, see below). The measure's share of each pixel sharpens as the cut shrinks (1/8: L1
    // about 0.02 from a long chaos game, for several times the work). For coverage a 1-pixel
    // piece over a pixel corner often reaches only some of the four pixels its spread points
    // land in, so coverage cuts at 1/2 pixel, where the tree's set agrees closely with a long
    // chaos game; pruning covered pixels (JobCoverage) pays for the extra level.
    const ParameterValues values(renderer, options);
    cut = values.automatic("cut") ? (options.binary ? 0.5 : 1.0) : values.number("cut", 1.0 / 64.0, 1.0);
    channels = ifs.dim() - ifs.spatial_dims();
    spatial = ifs.spatial_dims();
    center = box_center(plan);  // leaves plot at the centre of their piece's box
    if (options.binary) {
      for (const Point& p : ifs.fixed_points())
        if (std::isfinite(p[0])) spread.push_back(p);
    } else {
      spread.push_back(center);
    }
    if (spread.empty()) spread.push_back(ifs.start_point());
    spread_share.assign(spread.size(), 1.0 / static_cast<double>(spread.size()));
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
    for (int c = 0; c < ifs.dim(); ++c)
      for (const Point& p : spread) spread_by_coordinate.push_back(p[c]);
    // Pieces that stay wider than a pixel in one direction while thinning in the other (a rough
    // fractal interpolation graph) would split for ever: each group of jobs has a node budget
    // (NodeCounts), so that the outcome does not depend on the thread count. 128 nodes per
    // pixel (at least 2^24 in all) is several times what a hyperbolic system needs.
    const std::uint64_t total = std::max<std::uint64_t>(std::uint64_t(1) << 24, 128 * std::uint64_t(pixels()));
    if (fit_pixels) {
      // The budget belongs to the uniform plan's address prefixes (as many as its jobs, at
      // least 64): a runaway piece trips its group's budget early wherever its jobs run.
      groups = plan.jobs;
      budget = std::max<std::uint64_t>(1u << 12, total / groups);
    }
    // Coverage (binary) prunes pixels its job has covered, which pays most in large jobs: only
    // the measure is cut by work.
    if (fit_pixels && !binary) {
      // The work of a piece grows with the pixels its box covers on the image (a segment of
      // the fern's stem has no area but its length): jobs cut by it keep both cores busy to
      // the end, and each job's list of leaves small.
      balance_jobs(ifs, plan, [&](const AffineMap& m) {
        double lo[2], hi[2];
        piece_pixel_box(frame, plan, m, lo, hi);
        const double w = std::min<double>(hi[0], frame.width()) - std::max(lo[0], 0.0);
        const double h = std::min<double>(hi[1], frame.height()) - std::max(lo[1], 0.0);
        return w >= 0.0 && h >= 0.0 ? (w + 1.0) * (h + 1.0) : 0.0;
      });
    }
  }

  /// The extent of the piece's box M(B) toward the viewer, in pixels (3D systems).
  double depth_extent(const AffineMap& m) const {
    const auto& toward = frame.toward_viewer();
    double extent = 0.0;
    for (int c = 0; c < ifs.dim(); ++c) {
      double row = 0.0;
      for (int r = 0; r < 3; ++r) row += toward[r] * m.a(r, c);
      extent += std::abs(row) * plan.half[c];
    }
    return 2.0 * extent / frame.pixel_size();
  }

  NodeCounts node_counts() const { return NodeCounts(groups, budget); }

  /// The group of an address at least `plan.prefix` long: its first prefix digits.
  std::uint64_t group_of(const std::uint32_t* address) const {
    std::uint64_t g = 0;
    for (int level = 0; level < plan.prefix; ++level) g = g * ifs.size() + address[level];
    return g;
  }

  std::size_t pixels() const { return std::size_t(frame.width()) * frame.height(); }

  /// Empties `covered` over the pixels of the job's root piece (its address prefix), clipped
  /// to the image: every leaf of the job lies in that piece.
  void start_coverage(std::uint64_t job, JobCoverage& covered) const {
    AffineMap root(ifs.dim());
    for (std::uint32_t i : job_address(ifs, plan, job)) root = root.compose(ifs.map(i));
    double lo[2], hi[2];
    piece_pixel_box(frame, plan, root, lo, hi);
    auto clip = [](double v, int n) { return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(v)), 0, n); };
    covered.reset(clip(lo[0], frame.width()), clip(lo[1], frame.height()), clip(hi[0], frame.width() - 1) + 1,
                  clip(hi[1], frame.height() - 1) + 1);
  }

  /// The leaves of one job that land on the image, in the walk's order (those close together
  /// on one pixel summed through `sums`, the thread's), into `list` (cleared first, its
  /// buffers kept), its nodes counted into `counts`; OverBudget.
  void job(std::uint64_t job, LeafList& list, PixelSums& sums, NodeCounts& counts) const {
    const double w = frame.width(), h = frame.height();
    // The pieces' maps straight to pixels, level by level (to_pixel[k] for the node of length
    // k stop() saw last: the walk asks stop() about every node above the deepest level, parents
    // before children), and the box of the last.
    std::vector<PixelTransform> to_pixel(static_cast<std::size_t>(plan.max_depth) + 1);
    frame.pixel_transform(AffineMap(ifs.dim()), to_pixel[0]);
    double lo[2], hi[2];
    auto pixel_box = [&](const RecursionNode& node) {
      PixelTransform& t = to_pixel[node.length];
      to_pixel[node.length - 1].compose(ifs.map(node.address[node.length - 1]), t);
      t.box(plan.center.data(), plan.half.data(), lo, hi);
    };
    const bool prune = binary && fit_pixels;
    if (prune) start_coverage(job, list.covered);
    bool pruned = false;
    auto stop = [&](const RecursionNode& node) {
      pixel_box(node);
      if (hi[0] < 0.0 || lo[0] >= w || hi[1] < 0.0 || lo[1] >= h) return true;  // misses the image
      if (!fit_pixels) return false;
      if (prune) {
        std::int64_t x0, x1, y0, y1;
        covered_cells(lo[0], hi[0], x0, x1);
        covered_cells(lo[1], hi[1], y0, y1);
        if (list.covered.all(std::max<std::int64_t>(x0, 0), std::max<std::int64_t>(y0, 0),
                             std::min<std::int64_t>(x1, frame.width() - 1),
                             std::min<std::int64_t>(y1, frame.height() - 1)))
          return pruned = true;
      }
      // In 3D a leaf's depth is its centre's: a piece also thinner than a pixel toward the
      // viewer keeps the z-buffer within half a pixel of its nearest point.
      return (in_one_cell(lo, hi, 2) || std::max(hi[0] - lo[0], hi[1] - lo[1]) < cut) &&
             (spatial != 3 || depth_extent(node.map) < 1.0);
    };
    list.clear();
    // `px` is p's pixel position (to_pixel(p)); p itself is read for depth and channels only.
    auto plot = [&](const std::array<double, 2>& px, const Point& p, double mass) {
      if (!(px[0] >= 0.0 && px[0] < w && px[1] >= 0.0 && px[1] < h)) return;
      const auto x = std::size_t(px[0]), y = std::size_t(px[1]);
      if (prune) list.covered.set(std::int64_t(x), std::int64_t(y));
      sums.add(list, x, y, static_cast<std::uint32_t>(y * frame.width() + x), mass,
               spatial == 3 ? static_cast<float>(frame.depth(p)) : 0.0f, p.data() + spatial);
    };
    // A piece's spread images in pixel space, and (2D, no channels: nothing else is read from
    // them) their masses merged per pixel: a piece under a pixel reaches at most four, where
    // its images are nine or more.
    const bool merge = spatial == 2 && channels == 0;
    const std::size_t count = spread.size();
    std::vector<double> xs(count), ys(count), weight(count), merged_mass;
    std::vector<std::size_t> cell_of(count), merged;
    Point image{};
    // Nodes are counted into their group in batches; a node above the groups' level (in a
    // job's address only) is not counted.
    std::uint64_t group = 0, pending = 0;
    auto flush = [&] {
      if (pending) counts.add(group, pending);
      pending = 0;
    };
    auto counted_stop = [&](const RecursionNode& node) {
      if (budget && node.length >= plan.prefix) {
        if (node.length == plan.prefix || pending == 0) {
          flush();
          group = group_of(node.address);
        }
        if (++pending == 4096) flush();
      }
      return stop(node);
    };
    walk_job(ifs, plan, job, counted_stop, [&](const RecursionNode& node) {
      if (pruned) {
        pruned = false;
        return;
      }
      // At a fixed depth a leaf is one point (the seed's PRR; its mass is exact), except that
      // coverage spreads a leaf over two pixels wide (the fallback's) over points of its
      // piece, as the pixel stop does: the centre of a big piece's box may lie in a hole.
      if ((fit_pixels || binary) && node.length >= plan.max_depth) pixel_box(node);
      const bool spreads = fit_pixels || (binary && std::max(hi[0] - lo[0], hi[1] - lo[1]) > 2.0);
      if (!spreads || in_one_cell(lo, hi, 2)) {
        image = node.map(center);
        plot(frame.to_pixel(image), image, node.mass);
        return;
      }
      // Only the images strictly inside a pixel (a point on a pixel edge belongs to
      // neither side), as LeafPlotter::plot_spread does; their shares carry all the mass.
      // The images' pixel positions coordinate by coordinate over all points (vectorised).
      const PixelTransform& piece = to_pixel[node.length];
      std::fill(xs.begin(), xs.end(), piece.b[0]);
      std::fill(ys.begin(), ys.end(), piece.b[1]);
      for (int c = 0; c < piece.dim; ++c) {
        const double ax = piece.a[0][c], ay = piece.a[1][c], *s = spread_by_coordinate.data() + c * count;
        for (std::size_t k = 0; k < count; ++k) {
          xs[k] += ax * s[k];
          ys[k] += ay * s[k];
        }
      }
      for (std::size_t k = 0; k < count; ++k)
        weight[k] = on_cell_edge(xs[k]) || on_cell_edge(ys[k]) ? 0.0 : spread_share[k];
      double inside = 0.0;
      for (std::size_t k = 0; k < count; ++k) inside += weight[k];
      if (inside == 0.0) {
        std::copy(spread_share.begin(), spread_share.end(), weight.begin());
        inside = 1.0;
      }
      const double scale = node.mass / inside;
      merged.clear();
      merged_mass.clear();
      for (std::size_t k = 0; k < count; ++k) {
        if (weight[k] == 0.0) continue;
        if (!merge) {
          image = node.map(spread[k]);
          plot({xs[k], ys[k]}, image, scale * weight[k]);
          continue;
        }
        // The first image in each pixel stands for the pixel (its position is all plot reads).
        if (!(xs[k] >= 0.0 && xs[k] < w && ys[k] >= 0.0 && ys[k] < h)) continue;
        cell_of[k] = std::size_t(ys[k]) * frame.width() + std::size_t(xs[k]);
        std::size_t m = 0;
        while (m < merged.size() && cell_of[merged[m]] != cell_of[k]) ++m;
        if (m == merged.size()) {
          merged.push_back(k);
          merged_mass.push_back(0.0);
        }
        merged_mass[m] += scale * weight[k];
      }
      for (std::size_t m = 0; m < merged.size(); ++m)
        plot({xs[merged[m]], ys[merged[m]]}, image, merged_mass[m]);
    });
    flush();
    sums.flush(list);
  }

  std::vector<PixelSums> thread_sums(const RenderOptions& options) const {
    return std::vector<PixelSums>(static_cast<std::size_t>(resolve_threads(options.threads)),
                                  PixelSums(channels, spatial == 3));
  }
};

}  // namespace

Capabilities PointRecursive::capabilities() const {
  // Pieces cut at the pixel under node budgets, polar maps by their own rule. A map that
  // expands in space never gets below the cut: the budget's fallback then loses the
  // measure's thin parts, so such systems are refused.
  using C = Capabilities;
  return {C::Polar | C::Overlapping | C::Plane | C::Space};
}

Raster PointRecursive::draw(const Ifs& ifs, const RenderOptions& options) const {
  if (ifs.polar()) return polar::point_recursive(ifs, options, *this);  // non-linear maps: their own rule
  const PrrImage setup(ifs, options, *this);
  const Frame& frame = setup.frame;
  const std::size_t pixels = setup.pixels();
  const int channels = setup.channels;
  check_memory(pixels * (4.0 + 12.0 * channels + (channels ? 4.0 : 0.0)),
               "a " + std::to_string(frame.width()) + "x" + std::to_string(frame.height()) +
                   " point-recursive image");

  Raster raster;
  describe_channels(ifs, raster);
  raster.width = frame.width();
  raster.height = frame.height();
  raster.pixel_size = frame.pixel_size();
  std::vector<std::uint32_t> hits;
  std::vector<double> sums;
  // Density accumulates in single precision straight into the raster; a covered pixel is
  // kept above 0 even when its mass underflows. The buffers are made by the first list's
  // apply: their pages' zeroing (tens of MB at 4096^2) then overlaps the other threads' jobs.
  bool allocated = false;
  auto allocate = [&] {
    if (allocated) return;
    allocated = true;
    assign_large(raster.density, pixels, 0.0f);
    if (ifs.spatial_dims() == 3) assign_large(raster.depth, pixels, -std::numeric_limits<float>::infinity());
    assign_large(hits, channels ? pixels : 0, 0u);
    assign_large(sums, pixels * channels, 0.0);
  };
  constexpr float kCovered = std::numeric_limits<float>::denorm_min();

  // Results are applied strictly in job (address) order: floating-point sums come out the
  // same for any number of threads, or of cluster workers.
  std::mutex mutex;
  std::map<std::uint64_t, LeafList> waiting;
  // Applied lists keep their buffers for later jobs: growing a fresh list page by page for
  // every job cost more page faults and copies than the plotting itself.
  std::vector<LeafList> spare;
  std::uint64_t next_job = 0;
  bool applying = false;  // a thread is applying lists (outside the lock), in job order
  auto apply = [&](const LeafList& list) {
    allocate();
    for (std::size_t k = 0; k < list.pixel.size(); ++k) {
      const std::uint32_t px = list.pixel[k];
      raster.density[px] = std::max(raster.density[px] + list.mass[k], kCovered);
      raster.points += list.leaves[k];
      if (!list.depth.empty()) raster.depth[px] = std::max(raster.depth[px], list.depth[k]);
      if (!channels) continue;
      hits[px] += list.leaves[k];
      for (int c = 0; c < channels; ++c) sums[std::size_t(px) * channels + c] += list.channels[k * channels + c];
    }
  };
  auto fall_back = [&] {
    // A fixed depth has no budget: results saying otherwise came from another render (and
    // falling back again would never end).
    if (!setup.fit_pixels) throw InputError("image job result: over budget at a fixed depth (another render or build)");
    // The pixel-size stop would split for ever (or nearly): a fixed depth ends every branch,
    // whatever the system. Eq. 59's N^L >= H V leaves, one per pixel on average, leaves most
    // of a thin attractor's pixels empty (the maple leaf's, for one): the depth whose
    // N^L leaves match random iteration's count for coverage (Eq. 45) covers as it does. The
    // leaves carry exact masses, so the measure needs no more of them.
    RenderOptions fixed = options;
    const double leaves = static_cast<double>(default_iterations(frame.width(), frame.height(), true, 0.0));
    fixed.depth = ifs.size() < 2 ? setup.eq59
                                 : std::max(setup.eq59, static_cast<int>(std::ceil(std::log(leaves) /
                                                                                   std::log(double(ifs.size())))));
    return draw(ifs, fixed);
  };
  NodeCounts counts = setup.node_counts();
  if (options.distribute) {
    // Ranges come back in job order: applying them in turn is the address order. A group's
    // jobs may be split among workers: its count is known once every range is read (a raster
    // over budget is thrown away). One range at a time through one list: the whole render's
    // leaves decoded at once faulted in tens of MB only to be read once.
    LeafList list;
    try {
      for (std::string_view bytes : options.distribute(0, setup.plan.jobs, options.depth)) {
        list.clear();
        decode_leaves(bytes, !raster.depth.empty(), channels, pixels, list, counts);
        apply(list);
      }
    } catch (const OverBudget&) {
      return fall_back();
    }
  } else {
    std::vector<PixelSums> pixel_sums = setup.thread_sums(options);
    try {
      parallel_jobs(
          setup.plan.jobs, options.threads,
          [&](std::size_t job, int thread) {
            LeafList list;
            {
              std::lock_guard<std::mutex> lock(mutex);
              if (!spare.empty()) {
                list = std::move(spare.back());
                spare.pop_back();
              }
            }
            setup.job(job, list, pixel_sums[thread], counts);
            // One thread at a time applies the lists that are next in order, without the lock:
            // held through the adding, it stopped every other thread at the end of its job
            // (the adding is most of a sparse attractor's serial time). The applying thread
            // takes the lists that arrive meanwhile too.
            std::unique_lock<std::mutex> lock(mutex);
            waiting.emplace(job, std::move(list));
            if (applying) return;
            applying = true;
            for (auto it = waiting.find(next_job); it != waiting.end(); it = waiting.find(next_job)) {
              LeafList ready = std::move(it->second);
              waiting.erase(it);
              lock.unlock();
              apply(ready);
              lock.lock();
              spare.push_back(std::move(ready));
              ++next_job;
            }
            applying = false;
          },
          options.progress);
    } catch (const OverBudget&) {
      return fall_back();
    }
  }

  allocate();
  assign_large(raster.channels, pixels * channels, 0.0f);
  for (std::size_t i = 0; channels && i < pixels; ++i)
    for (int c = 0; c < channels && hits[i]; ++c)
      raster.channels[i * channels + c] = static_cast<float>(sums[i * channels + c] / hits[i]);
  return raster;
}

std::string PointRecursive::draw_jobs(const Ifs& ifs, const RenderOptions& options, std::uint64_t first,
                                      std::uint64_t last) const {
  if (ifs.polar()) return polar::point_recursive_jobs(ifs, options, *this, first, last);
  const PrrImage setup(ifs, options, *this);
  last = std::min(last, setup.plan.jobs);
  std::vector<LeafList> lists(last > first ? last - first : 0);
  NodeCounts counts = setup.node_counts();
  std::vector<PixelSums> pixel_sums = setup.thread_sums(options);
  try {
    parallel_jobs(
        lists.size(), options.threads,
        [&](std::size_t k, int thread) { setup.job(first + k, lists[k], pixel_sums[thread], counts); },
        options.progress);
  } catch (const OverBudget&) {
    return encode_leaves({}, true, counts, setup.channels);
  }
  return encode_leaves(lists, false, counts, setup.channels);
}

}  // namespace ifsforge
