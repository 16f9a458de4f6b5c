#pragma once
/// @file Addresses of points (seed 3.3.1): which pieces w_{a0} o ... o w_{a_{L-1}}(A) of the
/// attractor hold the attractor point nearest to a given point, found by descending the
/// hierarchy of the pieces' bounding boxes (branch and bound). Addresses follow the convention
/// of vector/addresses.h (a0 is the outermost map).
#include <cstdint>
#include <vector>

#include "ifsforge/model/ifs.h"

namespace ifsforge {

struct PointAddresses {
  std::vector<std::vector<std::uint16_t>> addresses;  ///< every piece within reach, sorted
  double distance = 0;  ///< upper bound on the distance from the point to the attractor
};

/// @brief The depth-`depth` addresses of the pieces that may hold the attractor point nearest to
/// `point` (spatial coordinates): those whose bounding box (of the image of a ball holding the
/// attractor) is no farther from it than `distance`, the nearest attractor point found. A hyperbolic system is required; InputError for a depth outside
/// 1..64 or a point of the wrong dimension.
PointAddresses address_of(const Ifs& ifs, const std::vector<double>& point, int depth);

}  // namespace ifsforge
