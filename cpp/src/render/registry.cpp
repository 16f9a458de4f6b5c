#include <cmath>
#include <memory>

#include "ifsforge/core/error.h"
#include "ifsforge/render/chaos_game.h"
#include "ifsforge/render/colour_stealing.h"
#include "ifsforge/render/point_recursive.h"

namespace ifsforge {
namespace {

struct Entry {
  std::unique_ptr<Renderer> renderer;
  std::vector<std::string> aliases;
};

const std::vector<Entry>& registry() {
  static const std::vector<Entry> entries = [] {
    std::vector<Entry> e;
    e.push_back({std::make_unique<ChaosGame>(), {"ria", "random"}});
    e.push_back({std::make_unique<ColourStealing>(), {"cs-ria", "color-stealing"}});
    e.push_back({std::make_unique<PointRecursive>(), {"point-recursive"}});
    return e;
  }();
  return entries;
}

}  // namespace

const Renderer& renderer(const std::string& name) {
  std::string known;
  for (const auto& entry : registry()) {
    if (entry.renderer->name() == name) return *entry.renderer;
    for (const auto& alias : entry.aliases)
      if (alias == name) return *entry.renderer;
    known += (known.empty() ? "" : ", ") + entry.renderer->name();
  }
  throw InputError("unknown algorithm '" + name + "'; choose one of: " + known);
}

std::vector<const Renderer*> renderers() {
  std::vector<const Renderer*> out;
  for (const auto& entry : registry()) out.push_back(entry.renderer.get());
  return out;
}

std::uint64_t default_iterations(int width, int height, bool binary, double points_per_pixel) {
  const double pixels = static_cast<double>(width) * height;
  if (binary) return static_cast<std::uint64_t>(pixels * std::log(1.78107 * pixels));  // Eq. 45
  return static_cast<std::uint64_t>(pixels * 8.0 * points_per_pixel);                  // Eq. 44
}

int default_depth(std::size_t maps, int width, int height) {
  if (maps < 2) return 1;
  const double pixels = static_cast<double>(width) * height;
  return static_cast<int>(std::ceil(std::log(pixels) / std::log(static_cast<double>(maps))));  // Eq. 59
}

}  // namespace ifsforge
