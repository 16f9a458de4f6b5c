#pragma once
// The "polar" map kind of system files (seed 3.3.3, Eq. 32), private to src/io: read beside
// the affine maps in ifs_json.cpp.
#include <string>

#include "ifsforge/model/polar_map.h"
#include "json_reader.h"

namespace ifsforge::detail {

/// {"center": [px, py], "k": k, "F": [f0..f5], "G": [g0..g3], "winding": w (default 1)}
PolarMap read_polar_map(const JsonReader& r, const json& j, const std::string& path);

/// The object read_polar_map reads (every field written, so a file states its whole map).
json polar_map_json(const PolarMap& map);

}  // namespace ifsforge::detail
