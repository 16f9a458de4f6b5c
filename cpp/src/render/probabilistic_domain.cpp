#include "ifsforge/render/probabilistic_domain.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "ifsforge/core/parallel.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/model/recurrent.h"
#include "ifsforge/render/leaf_plotter.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/piece_work.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {
namespace {

/// A node: the piece M(A_s) with its weight and level (M is kept beside it, flat).
struct Node {
  std::uint32_t piece;
  double weight;
  int length;
};

/// Nodes and their maps, as a stack (depth first) or a list (breadth first).
struct Nodes {
  std::vector<Node> nodes;
  std::vector<double> maps;  ///< stride doubles per node
  void push(const Node& node, const double* map, int stride) {
    nodes.push_back(node);
    maps.insert(maps.end(), map, map + stride);
  }
  void pop(int stride) {
    nodes.pop_back();
    maps.resize(maps.size() - stride);
  }
};

/// Points of each piece A_s spread over it: a point of A_s, the extremes of a seeded walk of
/// the chain in every spatial direction (the point just after w_s lies on A_s), and images
/// w_s of points of the pieces that may precede s.
std::vector<std::vector<Point>> piece_spreads(const Ifs& ifs) {
  const std::size_t n = ifs.size();
  const TransitionMatrix p = effective_transitions(ifs);
  const MapChain chain(ifs);
  const std::vector<Point> points = piece_points(ifs);
  const int k = ifs.spatial_dims();
  std::vector<std::vector<Point>> spreads(n);
  for (std::size_t s = 0; s < n; ++s) spreads[s].assign(2 * k + 1, points[s]);
  Rng rng(0x5EED5, 0);
  Point x = points[0];
  std::uint32_t state = 0;
  for (int step = 0; step < (1 << 15); ++step) {
    state = chain.next(state, rng.next());
    x = ifs.map(state)(x);
    if (step < 100) continue;
    auto& e = spreads[state];
    for (int axis = 0; axis < k; ++axis) {
      if (x[axis] < e[1 + 2 * axis][axis]) e[1 + 2 * axis] = x;
      if (x[axis] > e[2 + 2 * axis][axis]) e[2 + 2 * axis] = x;
    }
  }
  // A level of images: w_s(point of A_i) lies on A_s when i may precede s.
  for (std::size_t s = 0; s < n; ++s)
    for (std::size_t i = 0; i < n; ++i)
      if (p(i, s) > 0.0)
        for (std::size_t k = 0; k < 2; ++k) spreads[s].push_back(ifs.map(s)(spreads[i][k]));
  return spreads;
}

}  // namespace

Capabilities ProbabilisticDomain::capabilities() const {
  // One address tree per piece down to the pixel: a map that expands never gets there;
  // overlapping pieces are bounded by the estimate in draw().
  using C = Capabilities;
  return {C::Recurrent | C::Overlapping | C::Plane | C::Space};
}

Raster ProbabilisticDomain::draw(const Ifs& ifs, const RenderOptions& options) const {
  const ParameterValues params(*this, options);
  ifs.require_attractor();
  const std::size_t n = ifs.size();
  const int component = params.automatic("component") ? -1 : static_cast<int>(params.integer("component", 0, n - 1));
  const Frame frame = Frame::fit(ifs, options.width, options.height, options.window, options.view);
  const TransitionMatrix forward = effective_transitions(ifs);
  const std::vector<double> m = ifs.recurrent() ? forward.stationary() : ifs.probabilities();
  // r(s, i) = m_i P(i, s) / m_s (Eq. 73): the share of A_s that w_s brings from A_i.
  std::vector<double> r(n * n, 0.0);
  for (std::size_t s = 0; s < n; ++s)
    for (std::size_t i = 0; i < n; ++i)
      if (m[s] > 0.0) r[s * n + i] = m[i] * forward(i, s) / m[s];
  const std::vector<std::vector<Point>> spreads = piece_spreads(ifs);
  const int dim = ifs.dim(), stride = composed::size(dim);
  const PieceBoxes boxes(ifs, frame);
  const int fixed = options.depth > 0 ? std::min(options.depth, 64) : 0;
  std::optional<PieceBudget> budget;  // automatic depth: down to the pixel, within a budget of pieces
  if (!fixed) budget.emplace(ifs, frame, 1.0, name());
  LeafPlotter plotter(ifs, frame);
  // Visits the children M o w_s (A_i) of a node (its map `map`): leaves are plotted into
  // `batch`, the others pushed onto `keep`.
  auto expand = [&](const Node node, const double* map, LeafPlotter::Batch& batch, std::uint64_t& visited, Nodes& keep) {
    double child[composed::size(kMaxDim)];
    composed::before(map, ifs.map(node.piece), dim, child);
    const int length = node.length + 1;
    const PieceFit fit = fixed ? PieceFit::Split : boxes.fit(child);
    ++visited;
    if (fit == PieceFit::Off) return;  // M o w_s (B) holds every child's piece
    if (!fixed && (fit != PieceFit::Split || length >= 64)) {
      // Every child would be a leaf: together they are M(A_s), this node's own piece
      // (A_s = w_s(union of the A_i that may precede s)), so it is plotted once.
      if (fit == PieceFit::Small)
        plotter.plot_spread(batch, map, spreads[node.piece], node.weight);
      else
        plotter.plot(batch, composed::apply(map, dim, spreads[node.piece][0]), node.weight);
      return;
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!(r[node.piece * n + i] > 0.0)) continue;
      const double weight = node.weight * r[node.piece * n + i];
      if (fixed && length >= fixed)
        plotter.plot(batch, composed::apply(child, dim, spreads[i][0]), weight);
      else
        keep.push(Node{static_cast<std::uint32_t>(i), weight, length}, child, stride);
    }
  };
  // The first levels on one thread, breadth first, until there are enough nodes for the jobs.
  Nodes level;
  std::vector<double> identity(stride);
  composed::identity(dim, identity.data());
  for (std::size_t j = 0; j < n; ++j)
    if (component < 0 || component == static_cast<int>(j))
      level.push(Node{static_cast<std::uint32_t>(j), m[j], 0}, identity.data(), stride);
  LeafPlotter::Batch first;
  std::uint64_t operations = 0;
  while (!level.nodes.empty() && level.nodes.size() < 64) {
    Nodes next;
    for (std::size_t k = 0; k < level.nodes.size(); ++k) expand(level.nodes[k], &level.maps[k * stride], first, operations, next);
    level = std::move(next);
  }
  plotter.submit(0, std::move(first));
  std::vector<std::uint64_t> visited(level.nodes.size(), 0);
  parallel_jobs(level.nodes.size(), options.threads, [&](std::size_t job, int) {
    LeafPlotter::Batch batch;
    Nodes stack;
    stack.push(level.nodes[job], &level.maps[job * stride], stride);
    double map[composed::size(kMaxDim)];
    std::uint64_t counted = 0;
    for (std::uint64_t popped = 1; !stack.nodes.empty(); ++popped) {
      if ((popped & 0xFFF) == 0) {
        if (stop_requested()) throw Cancelled();
        if (budget) budget->spend(visited[job] - counted);
        counted = visited[job];
      }
      const Node node = stack.nodes.back();
      std::copy(stack.maps.end() - stride, stack.maps.end(), map);
      stack.pop(stride);
      expand(node, map, batch, visited[job], stack);
    }
    plotter.submit(job + 1, std::move(batch));
  }, options.progress);
  for (std::uint64_t v : visited) operations += v;
  Raster raster = plotter.finish();
  raster.points = operations;
  return raster;
}

}  // namespace ifsforge
