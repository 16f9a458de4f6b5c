#pragma once
// The systems the benchmarks draw, built in code so that a benchmark program carried to another
// machine needs no sample files: the Barnsley fern and the Sierpinski triangle (2D) or
// tetrahedron (3D).
#include <vector>

#include "ifsforge/model/ifs.h"

namespace bench {

inline ifsforge::Ifs fern() {
  using ifsforge::AffineMap;
  return ifsforge::Ifs("fern", ifsforge::ChannelLayout("xy"),
                       {AffineMap(2, {0, 0, 0, 0.16}, {0, 0}), AffineMap(2, {0.85, 0.04, -0.04, 0.85}, {0, 1.6}),
                        AffineMap(2, {0.2, -0.26, 0.23, 0.22}, {0, 1.6}),
                        AffineMap(2, {-0.15, 0.28, 0.26, 0.24}, {0, 0.44})},
                       {0.01, 0.85, 0.07, 0.07});
}

inline ifsforge::Ifs sierpinski(int dim = 2) {
  std::vector<ifsforge::AffineMap> maps;
  const double corners[4][3] = {{0, 0, 0}, {0.5, 0, 0}, {0.25, 0.5, 0}, {0, 0, 0.5}};
  for (int i = 0; i < (dim == 2 ? 3 : 4); ++i) {
    std::vector<double> a(dim * dim, 0.0), b(corners[i], corners[i] + dim);
    for (int k = 0; k < dim; ++k) a[k * dim + k] = 0.5;
    maps.emplace_back(dim, a, b);
  }
  return ifsforge::Ifs("sierpinski", ifsforge::ChannelLayout(dim == 2 ? "xy" : "xyz"), maps,
                       std::vector<double>(maps.size(), 1.0));
}

}  // namespace bench
