#pragma once
// Helpers shared by the rendering-algorithm suites (test_algorithms.cpp, test_algorithm_models.cpp).
#include <cstddef>
#include <map>
#include <string>
#include <utility>

#include "ifsforge/render/renderer.h"
#include "sample_systems.h"

namespace ifsforge::algorithms_test {

using sample_systems::sample;

/// Options on the sample's own window (so every renderer uses the same frame).
inline RenderOptions on_window(const Ifs& ifs, int size, std::map<std::string, std::string> parameters = {}) {
  RenderOptions o;
  o.width = o.height = size;
  const auto& w = ifs.render_defaults().window;
  if (!w.empty()) o.window = Window{w[0], w[1], w[2], w[3]};
  o.binary = true;
  o.parameters = std::move(parameters);
  return o;
}

inline double iou(const Raster& a, const Raster& b) {
  std::size_t both = 0, either = 0;
  for (std::size_t i = 0; i < a.density.size(); ++i) {
    const bool x = a.density[i] > 0.0f, y = b.density[i] > 0.0f;
    both += x && y;
    either += x || y;
  }
  return either ? static_cast<double>(both) / either : 1.0;
}

}  // namespace ifsforge::algorithms_test
