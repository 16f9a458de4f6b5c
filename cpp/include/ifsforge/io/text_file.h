#pragma once
/// @file Reading a whole input file as text, within the size and memory limits.
#include <string>

namespace ifsforge {

/// @brief The largest input file read_text_file accepts (bytes).
constexpr long long kMaxTextFileBytes = 64ll << 20;

/// @brief The whole text of a file; FileError when it cannot be read (or is a folder),
/// InputError when it is larger than kMaxTextFileBytes, MemoryBudgetError when parsing it
/// would not fit the memory budget.
std::string read_text_file(const std::string& path);

}  // namespace ifsforge
