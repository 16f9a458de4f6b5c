#include "ifsforge/render/parameters.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"

namespace ifsforge {

void check_render_options(const RenderOptions& o) {
  auto refuse = [](const std::string& option, const std::string& what) { throw InputError(option + ": " + what); };
  if (o.width < 1 || o.width > 65535 || o.height < 1 || o.height > 65535)
    refuse("size", "expects 1..65535 pixels per side, got " + std::to_string(o.width) + "x" + std::to_string(o.height));
  if (o.iterations > kMaxIterations)
    refuse("iterations", "at most 10^12 points, got " + std::to_string(o.iterations));
  if (!(o.points_per_pixel > 0 && o.points_per_pixel <= kMaxPointsPerPixel))
    refuse("points_per_pixel", "expects a number in (0, 10^6], got " + std::to_string(o.points_per_pixel));
  if (o.skip > kMaxIterations) refuse("skip", "at most 10^12 points, got " + std::to_string(o.skip));
  if (o.depth < 0 || o.depth > kMaxDepth)
    refuse("depth", "expects 0 (automatic) to " + std::to_string(kMaxDepth) + ", got " + std::to_string(o.depth));
  if (o.threads < 0 || o.threads > kMaxThreads)
    refuse("threads", "expects 0 (every core) to " + std::to_string(kMaxThreads) + ", got " + std::to_string(o.threads));
  // A raster keeps counts, channel sums and per-thread partial rasters: ~64 bytes a pixel.
  check_memory(64.0 * o.width * o.height,
               "a " + std::to_string(o.width) + "x" + std::to_string(o.height) + " raster");
}

void check_parameters(const Renderer& renderer, const RenderOptions& options) {
  check_render_options(options);
  const auto declared = renderer.parameters();
  for (const auto& entry : options.parameters) {
    bool known = false;
    for (const auto& p : declared) known |= p.name == entry.first;
    if (known) continue;
    std::string names;
    for (const auto& p : declared) names += (names.empty() ? "" : ", ") + p.name;
    throw InputError("algorithm '" + renderer.name() + "' has no parameter '" + entry.first + "'" +
                     (names.empty() ? std::string("; it takes none") : "; it takes: " + names));
  }
}

ParameterValues::ParameterValues(const Renderer& renderer, const RenderOptions& options)
    : algorithm_(renderer.name()) {
  check_parameters(renderer, options);
  for (const auto& p : renderer.parameters()) values_[p.name] = p.default_value;
  for (const auto& entry : options.parameters) values_[entry.first] = entry.second;
}

const std::string& ParameterValues::text(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) throw InputError("algorithm '" + algorithm_ + "' has no parameter '" + name + "'");
  return it->second;
}

void ParameterValues::fail(const std::string& name, const std::string& expected) const {
  throw InputError("algorithm '" + algorithm_ + "': parameter " + name + "='" + text(name) + "': expected " +
                   expected);
}

double ParameterValues::number(const std::string& name, double lo, double hi) const {
  const std::string& t = text(name);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || *end != '\0' || errno != 0 || !std::isfinite(v) || v < lo || v > hi)
    fail(name, "a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

long long ParameterValues::integer(const std::string& name, long long lo, long long hi) const {
  const std::string& t = text(name);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(t.c_str(), &end, 10);
  if (t.empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
    fail(name, "a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

std::string ParameterValues::choice(const std::string& name, const std::vector<std::string>& allowed) const {
  const std::string& t = text(name);
  std::string list;
  for (const auto& a : allowed) {
    if (a == t) return t;
    list += (list.empty() ? "" : ", ") + a;
  }
  fail(name, "one of " + list);
}

}  // namespace ifsforge
