#include "ifsforge/render/string_rewriting.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/leaf_plotter.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/piece_work.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {

std::vector<std::string> rewrite_map_strings(const std::vector<std::string>& symbols,
                                             const std::string& separator, int length) {
  if (length < 1) throw InputError("string rewriting needs a length of at least 1");
  std::vector<std::string> string_a = symbols, string_b;
  for (int level = 1; level < length; ++level) {
    string_b.clear();
    string_b.reserve(string_a.size() * symbols.size());
    for (const std::string& str_j : string_a)
      for (const std::string& w : symbols) string_b.push_back(w + separator + str_j);
    string_a.swap(string_b);  // String_A = String_B
  }
  return string_a;
}

namespace {

/// String_A or String_B: each string as its composed map w_s1 o ... o w_sL (flat) and its
/// mass p_s1 ... p_sL; all strings of a list have the same length.
struct Strings {
  std::vector<double> maps;
  std::vector<double> mass;
  int length = 0;
};

}  // namespace

Capabilities StringRewriting::capabilities() const {
  // Address strings down to the pixel: a map that expands never gets there (the work has no
  // bound); overlapping pieces are bounded by the estimate in draw().
  using C = Capabilities;
  return {C::Overlapping | C::Plane | C::Space};
}

Raster StringRewriting::draw(const Ifs& ifs, const RenderOptions& options) const {
  check_parameters(*this, options);
  ifs.require_attractor();
  const Frame frame = Frame::fit(ifs, options.width, options.height, options.window, options.view);
  const int n = ifs.dim(), stride = composed::size(n);
  const std::size_t maps = ifs.size();
  const PieceBoxes boxes(ifs, frame);
  const Point center = boxes.center();  // leaves plot at the centre of their piece's box
  const std::vector<Point> spread = spread_points(ifs);
  const int fixed = options.depth > 0 ? std::min(options.depth, 64) : 0;
  // At a fixed depth every string of the level before the last may be kept: maps^(depth-1)
  // composed maps and masses, in two level buffers.
  if (fixed > 1)
    check_memory(std::pow(double(maps), fixed - 1) * (stride + 1) * 8.0 * 2.0,
                 "string rewriting to depth " + std::to_string(fixed) + " with " + std::to_string(maps) + " maps");
  // Automatic depth: strings are rewritten until they fit a pixel, within a budget of pieces
  // (overlapping pieces multiply faster than the pixels), each level's strings checked
  // against the memory budget before they are made.
  std::optional<PieceBudget> budget;
  if (!fixed) budget.emplace(ifs, frame, 1.0, name());
  const double level_bytes = maps * (stride + 1) * 8.0 * resolve_threads(options.threads);
  LeafPlotter plotter(ifs, frame);
  // Rewrites every string of `a` into its N successors STR w_k: finished strings are plotted
  // into `batch`, the others appended to `b`.
  auto rewrite = [&](const Strings& a, Strings& b, LeafPlotter::Batch& batch, std::uint64_t& written) {
    b.maps.clear();
    b.mass.clear();
    b.length = a.length + 1;
    double child[composed::size(kMaxDim)];
    for (std::size_t item = 0; item < a.mass.size(); ++item)
      for (std::size_t k = 0; k < maps; ++k) {
        composed::before(&a.maps[item * stride], ifs.map(k), n, child);  // the string STR w_k
        const double mass = a.mass[item] * ifs.probabilities()[k];
        ++written;
        const PieceFit fit = boxes.fit(child);
        if (fit == PieceFit::Off) continue;
        const bool last = fixed ? b.length >= fixed : b.length >= 64 || fit != PieceFit::Split;
        if (!last) {
          b.maps.insert(b.maps.end(), child, child + stride);
          b.mass.push_back(mass);
        } else if (fixed || fit != PieceFit::Small) {
          plotter.plot(batch, composed::apply(child, n, center), mass);
        } else {
          // Smaller than a pixel but maybe straddling: points spread over the piece.
          plotter.plot_spread(batch, child, spread, mass);
        }
      }
  };
  // The first rewrites on one thread, until there are enough strings for the jobs.
  Strings a, b;
  a.maps.resize(stride);
  composed::identity(n, a.maps.data());
  a.mass = {1.0};
  LeafPlotter::Batch first;
  std::uint64_t operations = 0;
  while (!a.mass.empty() && a.mass.size() < 256) {
    const std::uint64_t before = operations;
    rewrite(a, b, first, operations);
    if (budget) budget->spend(operations - before);
    std::swap(a, b);
  }
  plotter.submit(0, std::move(first));
  std::vector<std::uint64_t> written(a.mass.size(), 0);
  parallel_jobs(a.mass.size(), options.threads, [&](std::size_t job, int) {
    LeafPlotter::Batch batch;
    Strings mine, next;  // this job's String_A and String_B
    mine.maps.assign(a.maps.begin() + job * stride, a.maps.begin() + (job + 1) * stride);
    mine.mass = {a.mass[job]};
    mine.length = a.length;
    while (!mine.mass.empty()) {
      if (stop_requested()) throw Cancelled();
      if (!fixed) check_memory(level_bytes * mine.mass.size(), "the next level of string rewriting's strings");
      const std::uint64_t before = written[job];
      rewrite(mine, next, batch, written[job]);
      if (budget) budget->spend(written[job] - before);
      std::swap(mine, next);
    }
    plotter.submit(job + 1, std::move(batch));
  }, options.progress);
  for (std::uint64_t c : written) operations += c;
  Raster raster = plotter.finish();
  raster.points = operations;
  return raster;
}

}  // namespace ifsforge
