#include "polar_json.h"

#include <algorithm>

namespace ifsforge::detail {

PolarMap read_polar_map(const JsonReader& r, const json& j, const std::string& path) {
  r.only(j, path, {"center", "k", "F", "G", "winding"},
         "a polar map has center, k, F (6 numbers), G (4 numbers) and winding (Eq. 32)");
  for (const char* key : {"center", "k", "F", "G"})
    if (!j.contains(key)) r.fail(path, std::string("a polar map needs '") + key + "'");
  PolarMap p;
  const auto center = r.coefficients(j["center"], path + "/center", 2);
  p.center = {center[0], center[1]};
  p.k = r.number(j["k"], path + "/k");
  if (!(p.k > 0.0) || p.k > kMaxCoefficient)
    r.fail(path + "/k", "expected a number > 0 (and at most 1e9), found " + JsonReader::describe(j["k"]));
  const auto f = r.coefficients(j["F"], path + "/F", PolarMap::kF);
  std::copy(f.begin(), f.end(), p.f.begin());
  const auto g = r.coefficients(j["G"], path + "/G", PolarMap::kG);
  std::copy(g.begin(), g.end(), p.g.begin());
  if (j.contains("winding"))
    p.winding = r.integer(j["winding"], path + "/winding", -PolarMap::kMaxWinding, PolarMap::kMaxWinding);
  r.at(path, [&] { p.validate("polar map"); });
  return p;
}

json polar_map_json(const PolarMap& map) {
  json j = json::object();
  j["center"] = map.center;
  j["k"] = map.k;
  j["F"] = map.f;
  j["G"] = map.g;
  j["winding"] = map.winding;
  return j;
}

}  // namespace ifsforge::detail
