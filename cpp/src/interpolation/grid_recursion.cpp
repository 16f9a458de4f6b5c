#include "ifsforge/interpolation/grid_recursion.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"

namespace ifsforge {

GridRecursion::GridRecursion(std::size_t intervals, std::size_t samples)
    : intervals_(intervals), samples_(samples) {
  if (intervals < 2)
    throw InputError("fractal interpolation needs at least 2 intervals (3 data points), got " +
                     std::to_string(intervals));
  if (samples < 2) throw InputError("fractal interpolation needs at least 2 samples, got " + std::to_string(samples));
  if (samples >= (std::size_t(1) << 32) || intervals >= (std::size_t(1) << 31))
    throw InputError("too many samples for one fractal interpolation: " + std::to_string(samples));
  check_memory(double(samples) * (sizeof(Op) + sizeof(CycleTerm) + 2 * sizeof(std::uint32_t) + 1),
               "a fractal interpolation plan of " + std::to_string(samples) + " samples");

  const std::uint64_t n = intervals, k = samples - 1;
  auto map_of = [&](std::uint64_t t) { return std::min<std::uint64_t>(n * t / k, n - 1); };
  auto successor = [&](std::uint64_t t) { return n * t - map_of(t) * k; };

  enum : std::uint8_t { Unvisited, OnStack, Done };
  std::vector<std::uint8_t> state(samples, Unvisited);
  std::vector<std::uint32_t> stack, stack_position(samples, 0);
  ops_.reserve(samples);

  for (std::uint64_t start = 0; start < samples; ++start) {
    if (state[start] == Done) continue;
    stack.clear();
    std::uint64_t t = start;
    std::int64_t cycle_at = -1;  // stack position where a cycle closes, if one does
    for (;;) {
      if (state[t] == Done) break;
      if (state[t] == OnStack) {
        cycle_at = stack_position[t];
        break;
      }
      if ((n * t) % k == 0) {  // a data node: its value is given (Eq. 90)
        ops_.push_back({std::uint32_t(t), 0, 0, std::uint32_t(n * t / k), 0, Kind::Node});
        state[t] = Done;
        break;
      }
      state[t] = OnStack;
      stack_position[t] = static_cast<std::uint32_t>(stack.size());
      stack.push_back(static_cast<std::uint32_t>(t));
      t = successor(t);
    }
    if (cycle_at >= 0) {
      // f(q0) = sum_k P_k c_k + P_L f(q0) with P_k the product of the first k factors a22.
      const std::uint32_t head = stack[cycle_at];
      const std::uint32_t first = static_cast<std::uint32_t>(terms_.size());
      for (std::size_t p = cycle_at; p < stack.size(); ++p)
        terms_.push_back({static_cast<std::uint32_t>(successor(stack[p])), static_cast<std::uint32_t>(map_of(stack[p]))});
      ops_.push_back({head, 0, 0, first, static_cast<std::uint32_t>(stack.size() - cycle_at), Kind::Cycle});
      state[head] = Done;
    }
    // Unwind: each sample's successor is known by the time it is reached.
    for (std::size_t p = stack.size(); p-- > 0;) {
      const std::uint32_t q = stack[p];
      if (state[q] == Done) continue;
      ops_.push_back({q, static_cast<std::uint32_t>(successor(q)), static_cast<std::uint32_t>(map_of(q)), 0, 0, Kind::Step});
      state[q] = Done;
    }
  }
}

void GridRecursion::evaluate(const double* values, const double* a22, double* out) const {
  const std::size_t n = intervals_;
  // Eq. 94 on [x0, xN] = [0, 1]: a21_i = F_i - F_{i-1} - a22_i (F_N - F_0), b2_i = F_{i-1} - a22_i F_0.
  std::vector<double> a21(n), b2(n);
  for (std::size_t i = 0; i < n; ++i) {
    a21[i] = values[i + 1] - values[i] - a22[i] * (values[n] - values[0]);
    b2[i] = values[i] - a22[i] * values[0];
  }
  for (const Op& op : ops_) {
    switch (op.kind) {
      case Kind::Node:
        out[op.target] = values[op.index];
        break;
      case Kind::Step:
        out[op.target] = a21[op.map] * position(op.source) + b2[op.map] + a22[op.map] * out[op.source];
        break;
      case Kind::Cycle: {
        double sum = 0.0, product = 1.0;
        for (std::uint32_t k = 0; k < op.count && std::fabs(product) > 1e-300; ++k) {
          const CycleTerm& term = terms_[op.index + k];
          sum += product * (a21[term.map] * position(term.source) + b2[term.map]);
          product *= a22[term.map];
        }
        out[op.target] = sum / (1.0 - product);
        break;
      }
    }
  }
}

}  // namespace ifsforge
