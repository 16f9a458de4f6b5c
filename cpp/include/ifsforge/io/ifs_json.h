#pragma once
/// @file The `ifsforge/1` JSON format for one system (documented in docs/formats.md).
#include <string>

#include "ifsforge/model/ifs.h"

namespace ifsforge {

constexpr const char* kFormatVersion = "ifsforge/1";

/// @brief Parses one system; InputError names `source`, the JSON path (e.g. /maps/2/matrix)
/// or the line and column, and what was expected.
Ifs parse_ifs_json(const std::string& text, const std::string& source = "<json>");
Ifs read_ifs_json(const std::string& path);

/// @brief The canonical form: every map as matrix + offset + probability.
std::string to_ifs_json(const Ifs& ifs);
void write_ifs_json(const std::string& path, const Ifs& ifs);

}  // namespace ifsforge
