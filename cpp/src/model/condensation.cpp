#include "ifsforge/model/condensation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/model/ifs.h"

namespace ifsforge {

std::array<double, 4> Condensation::bounds() const {
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::array<double, 4> b{inf, inf, -inf, -inf};
  for (const auto* shapes : {&polylines, &polygons})
    for (const Path& path : *shapes)
      for (const auto& p : path) {
        b[0] = std::min(b[0], p[0]);
        b[1] = std::min(b[1], p[1]);
        b[2] = std::max(b[2], p[0]);
        b[3] = std::max(b[3], p[1]);
      }
  return b;
}

std::array<double, 4> condensation_attractor_box(const Ifs& ifs) {
  const std::array<double, 4> c = ifs.condensation().bounds();
  std::array<double, 4> box = c;
  auto grow = [](std::array<double, 4>& b, double x, double y) {
    b[0] = std::min(b[0], x);
    b[1] = std::min(b[1], y);
    b[2] = std::max(b[2], x);
    b[3] = std::max(b[3], y);
  };
  const Point start = ifs.start_point();
  grow(box, start[0], start[1]);
  // The box operator is a contraction for a hyperbolic IFS: iterate to its fixed point.
  for (int iteration = 0; iteration < 1000; ++iteration) {
    std::array<double, 4> next = c;
    for (const AffineMap& m : ifs.maps())
      for (int corner = 0; corner < 4; ++corner) {
        const double x = corner & 1 ? box[2] : box[0], y = corner & 2 ? box[3] : box[1];
        grow(next, m.a(0, 0) * x + m.a(0, 1) * y + m.b(0), m.a(1, 0) * x + m.a(1, 1) * y + m.b(1));
      }
    const double change = std::max({std::abs(next[0] - box[0]), std::abs(next[1] - box[1]),
                                     std::abs(next[2] - box[2]), std::abs(next[3] - box[3])});
    box = next;
    if (change <= 1e-12 * (box[2] - box[0] + box[3] - box[1])) break;
  }
  return box;
}

void Ifs::set_condensation(Condensation c) {
  if (c.empty()) {
    condensation_ = Condensation();
    return;
  }
  const std::string what = "the condensation set of '" + name_ + "'";
  if (spatial_dims() != 2) throw InputError(what + ": condensation sets are shapes in the plane (2D systems only)");
  for (std::size_t i = 0; i < maps_.size(); ++i)
    for (int r = 0; r < 2; ++r)
      for (int col = 2; col < dim(); ++col)
        if (maps_[i].a(r, col) != 0.0)
          throw InputError(what + ": map " + std::to_string(i + 1) +
                           " moves points by their color; condensation needs spatial rows that read x and y only");
  for (double s : spatial_contraction_factors())
    if (!(s < 1.0)) throw InputError(what + ": Theorem 2 needs a hyperbolic IFS (every map contracting)");
  for (const auto& path : c.polylines)
    if (path.size() < 2) throw InputError(what + ": a polyline needs at least 2 points");
  for (const auto& path : c.polygons)
    if (path.size() < 3) throw InputError(what + ": a polygon needs at least 3 points");
  for (const auto* shapes : {&c.polylines, &c.polygons})
    for (const auto& path : *shapes)
      for (const auto& p : path)
        if (!std::isfinite(p[0]) || !std::isfinite(p[1])) throw InputError(what + ": a point is not finite");
  if (static_cast<int>(c.channels.size()) != dim() - 2)
    throw InputError(what + ": layout '" + layout_.text() + "' needs " + std::to_string(dim() - 2) +
                     " channel values on the set, found " + std::to_string(c.channels.size()));
  for (double v : c.channels)
    if (!std::isfinite(v)) throw InputError(what + ": a channel value is not finite");
  if (!(c.probability >= 0.0 && c.probability < 1.0))
    throw InputError(what + ": its probability p_0 must be in [0, 1)");
  if (recurrent() || !super_.empty() || polar())
    throw InputError("system '" + name_ + "': a system with a condensation set cannot also be recurrent, a super IFS or have polar maps");
  condensation_ = std::move(c);
}

}  // namespace ifsforge
