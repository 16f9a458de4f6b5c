#include "ifsforge/inverse/address_of.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/vector/addresses.h"

namespace ifsforge {
namespace {

struct Node {
  std::vector<std::uint16_t> address;
  AffineMap map;  ///< w_{a0} o ... o w_{a_k}
  double lower;   ///< distance from the point to the piece's bounding box
};

}  // namespace

PointAddresses address_of(const Ifs& ifs, const std::vector<double>& point, int depth) {
  const int d = ifs.spatial_dims();
  if (static_cast<int>(point.size()) != d)
    throw InputError("system '" + ifs.name() + "' is " + std::to_string(d) + "D in space; got a point of " +
                     std::to_string(point.size()) + " coordinates");
  for (double v : point)
    if (!std::isfinite(v)) throw InputError("the point's coordinates must be finite numbers, got " + std::to_string(v));
  if (depth < 1 || depth > kMaxAddressDepth)
    throw InputError("the address depth must be 1.." + std::to_string(kMaxAddressDepth) + ", got " + std::to_string(depth));
  if (ifs.classify() != Classification::Hyperbolic)
    throw InputError("addresses need every map to contract; system '" + ifs.name() + "' does not");
  // A ball holding the attractor: centre c, radius R >= |w_i(c) - c| / (1 - s_i) maps into itself.
  const auto s = ifs.spatial_contraction_factors();
  Point c{};
  const auto fixed = ifs.fixed_points();
  for (const Point& f : fixed)
    for (int k = 0; k < d; ++k) c[k] += f[k] / fixed.size();
  double radius = 0;
  for (std::size_t i = 0; i < ifs.size(); ++i) {
    const Point w = ifs.map(i)(c);
    double r = 0;
    for (int k = 0; k < d; ++k) r += (w[k] - c[k]) * (w[k] - c[k]);
    radius = std::max(radius, std::sqrt(r) / (1 - s[i]));
  }
  radius *= 1 + 1e-9;
  const Point on = fixed[0];  // on the attractor: its images are too
  auto distance_to = [&](const Point& q) {
    double r = 0;
    for (int k = 0; k < d; ++k) r += (q[k] - point[k]) * (q[k] - point[k]);
    return std::sqrt(r);
  };
  // The bounding box of w(B), B the box around the ball: centre w(c), half-sides sum_j |A_kj| R.
  auto box_distance = [&](const AffineMap& w) {
    const Point centre = w(c);
    double r = 0;
    for (int k = 0; k < d; ++k) {
      double half = 0;
      for (int j = 0; j < d; ++j) half += std::abs(w.a(k, j)) * radius;
      const double gap = std::max(0.0, std::abs(point[k] - centre[k]) - half);
      r += gap * gap;
    }
    return std::sqrt(r);
  };
  PointAddresses out;
  out.distance = distance_to(on);
  std::vector<Node> level{{{}, AffineMap(ifs.dim()), 0.0}};
  for (int l = 0; l < depth; ++l) {
    std::vector<Node> next;
    for (const Node& n : level)
      for (std::size_t i = 0; i < ifs.size(); ++i) {
        Node child{n.address, n.map.compose(ifs.map(i)), 0.0};
        child.address.push_back(static_cast<std::uint16_t>(i));
        child.lower = box_distance(child.map);
        out.distance = std::min(out.distance, distance_to(child.map(on)));
        next.push_back(std::move(child));
      }
    // Keep the pieces that can hold the nearest point: their box is no farther than the best
    // attractor point known (touching pieces' boxes overlap: a point there keeps several).
    level.clear();
    for (Node& n : next)
      if (n.lower <= out.distance + 1e-12) level.push_back(std::move(n));
    if (level.size() > 1u << 16)
      throw InputError("the point has more than 65536 candidate pieces at depth " + std::to_string(l + 1) +
                       "; ask for a smaller depth");
  }
  for (const Node& n : level) out.addresses.push_back(n.address);
  std::sort(out.addresses.begin(), out.addresses.end());
  return out;
}

}  // namespace ifsforge
