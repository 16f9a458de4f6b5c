#pragma once
// The sample systems (samples/systems/<name>.json) the suites render, read one way by all of them:
// the unity build (tests/CMakeLists.txt) compiles several suites as one file, where a copy per
// suite would be a redefinition.
#include <string>

#include "ifsforge/io/ifs_json.h"

namespace ifsforge::sample_systems {

inline Ifs sample(const std::string& name) {
  return read_ifs_json(std::string(IFSFORGE_SOURCE_DIR) + "/samples/systems/" + name + ".json");
}

}  // namespace ifsforge::sample_systems
