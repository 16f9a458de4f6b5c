#pragma once
// Shared by the libFuzzer targets: ifsforge's own errors are the expected outcome of bad input;
// anything else (a crash, a sanitizer report, another exception) is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "ifsforge/core/error.h"

namespace fuzz {

/// Calls read(path) on a file holding the input (readers that take a path), named with `ext`.
template <typename Read>
void with_file(const std::uint8_t* data, std::size_t size, const char* ext, Read&& read) {
  const std::string path = "/tmp/ifsforge-fuzz-" + std::to_string(getpid()) + ext;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    read(path);
  } catch (const ifsforge::Error&) {
  }
  std::remove(path.c_str());
}

template <typename Parse>
void with_text(const std::uint8_t* data, std::size_t size, Parse&& parse) {
  try {
    parse(std::string(reinterpret_cast<const char*>(data), size));
  } catch (const ifsforge::Error&) {
  }
}

}  // namespace fuzz
