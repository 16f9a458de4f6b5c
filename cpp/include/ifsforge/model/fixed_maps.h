#pragma once
/// @file A system's maps with the dimension as a compile-time constant, so that hot loops
/// (random iteration in 2D images and in volumes) unroll.
#include <vector>

#include "ifsforge/model/ifs.h"

namespace ifsforge {

template <int N>
struct FixedMap {
  double a[N][N], b[N];
};

template <int N>
std::vector<FixedMap<N>> fixed_maps(const Ifs& ifs) {
  std::vector<FixedMap<N>> maps(ifs.size());
  for (std::size_t i = 0; i < ifs.size(); ++i)
    for (int r = 0; r < N; ++r) {
      for (int c = 0; c < N; ++c) maps[i].a[r][c] = ifs.map(i).a(r, c);
      maps[i].b[r] = ifs.map(i).b(r);
    }
  return maps;
}

}  // namespace ifsforge
