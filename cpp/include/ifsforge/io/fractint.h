#pragma once
/// @file Fractint `.ifs` files: `name { rows }` entries, 2D rows `a b c d e f p`
/// (x' = a x + b y + e, y' = c x + d y + f), 3D rows of 13 numbers when the name holds
/// "(3D)", `;` comments, numbers separated by spaces, tabs or commas.
#include <string>
#include <vector>

#include "ifsforge/model/ifs.h"

namespace ifsforge {

/// @brief Every entry, in file order; InputError names the file, the entry and the line.
std::vector<Ifs> parse_fractint(const std::string& text, const std::string& source = "<ifs>");
std::vector<Ifs> read_fractint(const std::string& path);

}  // namespace ifsforge
