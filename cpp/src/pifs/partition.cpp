#include "ifsforge/pifs/partition.h"

#include <functional>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/pifs/plane_coding.h"

namespace ifsforge {
namespace {

const PifsCandidate& candidate(const PifsCode& code, const PifsPlaneCandidates& c, int x, int y, int log) {
  const auto& level = c.levels[log - code.min_log];
  const int bx = c.padded_width >> log;
  return level[std::size_t(y >> log) * bx + (x >> log)];
}

int bits_for(int count) {
  int b = 0;
  while ((1 << b) < count) ++b;
  return b;
}

/// Visits the top-level blocks in raster order; `node` appends the leaves of one block.
void each_top(const PifsCode& code, const PifsPlaneCandidates& c, const std::function<void(int, int)>& node) {
  const int top = 1 << code.max_log;
  for (int y = 0; y < c.padded_height; y += top) {
    if (stop_requested()) throw Cancelled();  // a large plane's partition hears Ctrl-C
    for (int x = 0; x < c.padded_width; x += top) node(x, y);
  }
}

}  // namespace

std::vector<PifsLeaf> partition_threshold(const PifsCode& code, const PifsPlaneCandidates& c, double rms) {
  std::vector<PifsLeaf> leaves;
  std::function<void(int, int, int)> visit = [&](int x, int y, int log) {
    const PifsCandidate& k = candidate(code, c, x, y, log);
    const double limit = rms * rms * double(1 << log) * (1 << log);
    const bool flat_ok = k.flat_error <= limit || !k.has_transform || k.flat_error <= k.transform_error;
    const double err = flat_ok ? k.flat_error : k.transform_error;
    if (err <= limit || log == code.min_log) {
      leaves.push_back(flat_ok ? k.flat : k.transform);
      return;
    }
    const int h = 1 << (log - 1);
    visit(x, y, log - 1);
    visit(x + h, y, log - 1);
    visit(x, y + h, log - 1);
    visit(x + h, y + h, log - 1);
  };
  each_top(code, c, [&](int x, int y) { visit(x, y, code.max_log); });
  return leaves;
}

namespace {

/// The Lagrangian choice for one quadtree node: its leaves are appended to `out` (children's
/// leaves are appended in place and dropped again when the whole cell is cheaper, so nothing
/// is allocated per node).
struct LagrangianCut {
  // Rough bit prices (the range coder's real cost is measured by the rate control).
  static constexpr double kFlatBits = 5, kTransformBits = 11;
  const PifsCode& code;
  const PifsPlaneCandidates& c;
  double lambda, weight;
  double domain_bits[16];
  std::vector<PifsLeaf>& out;

  double best(int x, int y, int log) {
    const PifsCandidate& k = candidate(code, c, x, y, log);
    const double split_bit = log > code.min_log ? lambda : 0.0;
    double cost = weight * k.flat_error + lambda * kFlatBits + split_bit;
    const PifsLeaf* leaf = &k.flat;
    if (k.has_transform) {
      const double t = weight * k.transform_error + lambda * (kTransformBits + domain_bits[log]) + split_bit;
      if (t < cost) {
        cost = t;
        leaf = &k.transform;
      }
    }
    if (log > code.min_log) {
      const std::size_t mark = out.size();
      const int h = 1 << (log - 1);
      // One statement per child: their leaves must be appended in coding order.
      double split = split_bit;
      split += best(x, y, log - 1);
      split += best(x + h, y, log - 1);
      split += best(x, y + h, log - 1);
      split += best(x + h, y + h, log - 1);
      if (split < cost) return split;
      out.resize(mark);
    }
    out.push_back(*leaf);
    return cost;
  }
};

}  // namespace

std::vector<PifsLeaf> partition_lagrangian(const PifsCode& code, const PifsPlaneCandidates& c, double lambda,
                                           double weight) {
  std::vector<PifsLeaf> leaves;
  LagrangianCut cut{code, c, lambda, weight, {}, leaves};
  for (int log = code.min_log; log <= code.max_log; ++log)
    cut.domain_bits[log] = bits_for(domain_count(c.padded_width, log)) + bits_for(domain_count(c.padded_height, log));
  each_top(code, c, [&](int x, int y) { cut.best(x, y, code.max_log); });
  return leaves;
}

}  // namespace ifsforge
