#pragma once
// Systems and helpers shared by the vector IFS suites (test_vector.cpp, test_vector_files.cpp).
#include <unistd.h>

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "ifsforge/io/ifs_json.h"
#include "ifsforge/vector/instances.h"

namespace ifsforge::vector_test {

// Rotations about different axes make the maps non-commuting, so the order of an address matters.
inline AffineMap rotated(double scale, double degrees, int axis, std::array<double, 3> offset) {
  const double c = std::cos(degrees * M_PI / 180.0) * scale, s = std::sin(degrees * M_PI / 180.0) * scale;
  std::vector<double> m(9, 0.0);
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  m[axis * 3 + axis] = scale;
  m[a * 3 + a] = c;
  m[a * 3 + b] = -s;
  m[b * 3 + a] = s;
  m[b * 3 + b] = c;
  return AffineMap(3, m, {offset[0], offset[1], offset[2]});
}

inline Ifs twisted_tetrahedron() {
  return Ifs("twisted tetrahedron", ChannelLayout("xyz"),
             {rotated(0.5, 20, 2, {0, 0, 0}), rotated(0.5, -35, 0, {0.5, 0, 0}), rotated(0.45, 50, 1, {0.25, 0.45, 0}),
              rotated(0.5, 10, 2, {0.25, 0.15, 0.45})},
             {0.2, 0.3, 0.1, 0.4});
}

inline Ifs sierpinski_triangle() {
  return Ifs("sierpinski", ChannelLayout("xy"),
             {AffineMap(2, {0.5, 0, 0, 0.5}, {0, 0}), AffineMap(2, {0.5, 0, 0, 0.5}, {0.5, 0}),
              AffineMap(2, {0.5, 0, 0, 0.5}, {0.25, std::sqrt(3.0) / 4})},
             {1, 1, 1});
}

inline Ifs sample(const std::string& name) {
  return read_ifs_json(std::string(IFSFORGE_SOURCE_DIR) + "/samples/systems/" + name);
}

/// w_{a0} o w_{a1} o ... o w_{a_{L-1}} built with AffineMap::compose (not the walker's code).
inline AffineMap composition(const Ifs& ifs, const std::uint16_t* address, int length) {
  AffineMap m(ifs.dim());
  for (int i = 0; i < length; ++i) m = m.compose(ifs.map(address[i]));
  return m;
}

inline InstanceOptions explicit_base(int depth) {
  InstanceOptions o;
  o.depth = depth;
  o.base_point = {0.3, 0.2, 0.1};
  o.base_vector = {0.4, 0.1, -0.2};
  o.base_up = {0.0, 0.3, 0.5};
  return o;
}

/// A fresh folder per test run (scenes get their ifsforge.inc written beside them).
inline std::string temp_path(const std::string& name) {
  static const std::string folder = [] {
    std::string pattern = "/tmp/ifsforge_test_vector_XXXXXX";
    if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    return pattern;
  }();
  return folder + "/" + name;
}

inline std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace ifsforge::vector_test
