#include "ifsforge/render/parameters.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "ifsforge/core/error.h"

namespace ifsforge {

void check_parameters(const Renderer& renderer, const RenderOptions& options) {
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
