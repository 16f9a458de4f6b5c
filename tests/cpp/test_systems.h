#pragma once
// Test systems shared by the volume and occupancy suites: grid-aligned attractors whose occupied
// cells are known exactly (the Menger sponge: 20^k of 27^k; the tetrahedron: 4^k of 8^k).
#include <array>
#include <vector>

#include "ifsforge/model/ifs.h"

namespace ifsforge::test_systems {

/// A map x -> s x + t on the spatial part; with colour, channels -> gain * channels + colour.
inline AffineMap corner_map(int dim, double s, std::array<double, 3> t, double gain = 0.0,
                            const std::vector<double>& color = {}) {
  AffineMap m(dim);
  for (int a = 0; a < 3; ++a) {
    m.a(a, a) = s;
    m.b(a) = t[a];
  }
  for (int c = 3; c < dim; ++c) {
    m.a(c, c) = gain;
    m.b(c) = color[c - 3];
  }
  return m;
}

inline Ifs menger() {
  std::vector<AffineMap> maps;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        if ((i == 1) + (j == 1) + (k == 1) < 2) maps.push_back(corner_map(3, 1.0 / 3, {i / 3.0, j / 3.0, k / 3.0}));
  return Ifs("menger", ChannelLayout("xyz"), maps, std::vector<double>(20, 1.0));
}

/// The tetrahedron's corners and, for the coloured version, one constant colour per map.
inline const std::array<std::array<double, 3>, 4> kCorners = {{{0, 0, 0}, {0.5, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5}}};
inline const std::vector<std::vector<double>> kColors = {{0.9, 0.1, 0.2}, {0.1, 0.8, 0.3}, {0.2, 0.3, 0.95}, {0.7, 0.7, 0.1}};

inline Ifs tetrahedron(bool color = false) {
  std::vector<AffineMap> maps;
  for (int i = 0; i < 4; ++i) maps.push_back(corner_map(color ? 6 : 3, 0.5, kCorners[i], 0.0, kColors[i]));
  return Ifs("tetrahedron", ChannelLayout(color ? "xyz+rgb" : "xyz"), maps, {1, 1, 1, 1});
}

}  // namespace ifsforge::test_systems
