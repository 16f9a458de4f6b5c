#pragma once
/// @file Condensation sets (seed 3.1, Definitions 8-9, Theorem 2).
#include <array>
#include <vector>

namespace ifsforge {

class Ifs;

/// @brief The set C of the condensation map w_0(B) = C. Adding w_0 to a 2D IFS makes the
/// attractor C together with every image w_s(C) (a hyperbolic IFS with condensation, IFSC):
/// W(B) = C u w_1(B) u ... u w_N(B) (Eq. 15). C is given as shapes in the xy plane.
struct Condensation {
  using Path = std::vector<std::array<double, 2>>;
  std::vector<Path> polylines;  ///< open paths, drawn as lines
  std::vector<Path> polygons;   ///< closed, filled (even-odd rule)
  std::vector<double> channels; ///< values of the layout's extra channels on C (colour ...)
  /// p_0: the share of the invariant measure w_0 carries; the maps share 1 - p_0.
  double probability = 0.1;

  bool empty() const { return polylines.empty() && polygons.empty(); }
  /// @brief xmin, ymin, xmax, ymax of the shapes.
  std::array<double, 4> bounds() const;
};

/// @brief A box (xmin, ymin, xmax, ymax) holding the attractor of `ifs` with its condensation
/// set: the limit of B -> box(C) u box(w_1(B)) u ... started from box(C) and the attractor's
/// bounds (a fixed point of a contraction on boxes).
std::array<double, 4> condensation_attractor_box(const Ifs& ifs);

}  // namespace ifsforge
