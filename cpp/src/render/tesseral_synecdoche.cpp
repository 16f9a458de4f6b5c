#include "ifsforge/render/tesseral_synecdoche.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/cells.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/leaf_plotter.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/pixel_space.h"
#include "ifsforge/render/recursion.h"

namespace ifsforge {

Capabilities TesseralSynecdoche::capabilities() const {
  // Branches stop below a probability, whatever the pieces' sizes.
  using C = Capabilities;
  return {C::Overlapping | C::Plane | C::Space};
}

Raster TesseralSynecdoche::draw(const Ifs& ifs, const RenderOptions& options) const {
  const ParameterValues params(*this, options);
  ifs.require_attractor();
  const double pv = params.number("threshold", 0.0, 1.0);
  const Frame frame = Frame::fit(ifs, options.width, options.height, options.window, options.view);
  const int eq59 = default_depth(ifs.size(), frame.width(), frame.height());
  RecursionPlan plan = plan_recursion(ifs, options.depth, eq59);
  const bool fit_pixels = options.depth <= 0;
  if (fit_pixels) plan.max_depth = depth_for_size(ifs, plan, frame.pixel_size(), 2, eq59);
  const double w = frame.width(), h = frame.height();
  auto pixel_box = [&](const AffineMap& m, double* lo, double* hi) { piece_pixel_box(frame, plan, m, lo, hi); };
  enum class Why { Depth, Probability, OnePixel, Small, Off };
  auto why = [&](const RecursionNode& node) {
    double lo[2], hi[2];
    pixel_box(node.map, lo, hi);
    if (hi[0] < 0.0 || lo[0] >= w || hi[1] < 0.0 || lo[1] >= h) return Why::Off;
    if (node.mass < pv) return Why::Probability;
    if (fit_pixels && in_one_cell(lo, hi, 2)) return Why::OnePixel;
    if (fit_pixels && std::max(hi[0] - lo[0], hi[1] - lo[1]) < 1.0) return Why::Small;
    return Why::Depth;
  };
  const Point center = box_center(plan);  // leaves plot at the centre of their piece's box
  const std::vector<Point> spread = spread_points(ifs);
  LeafPlotter plotter(ifs, frame);
  std::vector<std::uint64_t> nodes(plan.jobs, 0);
  parallel_jobs(plan.jobs, options.threads, [&](std::size_t job, int) {
    LeafPlotter::Batch batch;
    std::uint64_t& count = nodes[job];
    walk_job(ifs, plan, job, [&](const RecursionNode& node) { ++count; return why(node) != Why::Depth; },
             [&](const RecursionNode& node) {
               if (node.length >= plan.max_depth) ++count;
               switch (why(node)) {
                 case Why::Off: return;
                 case Why::Small: plotter.plot_spread(batch, node.map, spread, node.mass); return;
                 default: plotter.plot(batch, node.map(center), node.mass);
               }
             });
    plotter.submit(job, std::move(batch));
  }, options.progress);
  Raster raster = plotter.finish();
  raster.points = 0;
  for (std::uint64_t c : nodes) raster.points += c;  // nodes of the address tree visited
  return raster;
}

}  // namespace ifsforge
