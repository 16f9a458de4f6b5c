#pragma once
/// @file Writing and reading .pifs files (their bytes: pifs/code_bytes.h).
#include <string>

#include "ifsforge/pifs/code_bytes.h"

namespace ifsforge {

/// @brief Writes atomically (no partial file on failure).
void write_pifs(const std::string& path, const PifsCode& code);
/// @brief Reads a .pifs file; FileError when unreadable, InputError naming the file when invalid.
PifsCode read_pifs(const std::string& path);

}  // namespace ifsforge
