#pragma once
/// @file A system named by a file spec, whatever its format.
#include <string>

#include "ifsforge/model/ifs.h"

namespace ifsforge {

/// @brief A system from "file.json", "file.ifs" (its first entry) or "file.ifs:entry".
Ifs load_system(const std::string& spec);

}  // namespace ifsforge
