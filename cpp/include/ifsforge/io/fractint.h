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

/// @brief A system from "file.json", "file.ifs" (its first entry) or "file.ifs:entry".
Ifs load_system(const std::string& spec);

/// @brief The largest input file read_text_file accepts (bytes).
constexpr long long kMaxTextFileBytes = 64ll << 20;

/// @brief The whole text of a file; FileError when it cannot be read (or is a folder),
/// InputError when it is larger than kMaxTextFileBytes, MemoryBudgetError when parsing it
/// would not fit the memory budget.
std::string read_text_file(const std::string& path);

}  // namespace ifsforge
