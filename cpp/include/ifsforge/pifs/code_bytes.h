#pragma once
/// @file The bytes of a .pifs file (the seed's Steps 5-6): magic "PIFS", version, image size, channels,
/// colour handling, quadtree and quantisation parameters, each plane's byte counts and residual
/// step, the planes' range-coded transforms and residuals, and a CRC-32 of everything before it.
/// Version 1 (no residual layer) is still read.
#include <cstdint>
#include <string>
#include <vector>

#include "ifsforge/pifs/code.h"

namespace ifsforge {

constexpr int kPifsVersion = 2;

/// @brief The coded sizes of one plane: its transforms, and its residual layer (step 0: none).
struct PifsStreamSizes {
  std::size_t transforms = 0;
  int residual_step = 0;
  std::size_t residual = 0;
};

/// @brief The file's bytes.
std::vector<std::uint8_t> pifs_to_bytes(const PifsCode& code);

/// @brief A code from a file's bytes; InputError naming `where` for a wrong magic or version,
/// a truncated or corrupted file (checksum, out-of-range field, stream not ending on time).
PifsCode pifs_from_bytes(const std::uint8_t* data, std::size_t size, const std::string& where = "PIFS data");

/// @brief Bytes of the header (everything before the first plane's stream and the checksum).
std::size_t pifs_header_size(const PifsCode& code);

/// @brief Bytes of the planes' residual layers.
std::size_t pifs_residual_bytes(const PifsCode& code);

/// @brief The size of pifs_to_bytes(code) when its planes' streams have `sizes`.
std::size_t pifs_file_size(const PifsCode& code, const std::vector<PifsStreamSizes>& sizes);

}  // namespace ifsforge
