#pragma once
/// @file Entropy coding of one plane's PIFS transforms (the seed's Step 6): quadtree split bits,
/// quantised s, the range mean predicted from its coded neighbours, isometry and domain cell,
/// each through adaptive models of the range coder.
#include <cstdint>
#include <string>
#include <vector>

#include "ifsforge/pifs/code.h"

namespace ifsforge {

/// @brief Bits spent on each part of a plane (measured, not estimated).
struct PifsPlaneCost {
  double quadtree = 0, contrast = 0, mean = 0, isometry = 0, domain = 0;
};

/// @brief The coded bytes of `plane` (leaves in coding order). `cost`, when given, receives the
/// bits spent on each part.
std::vector<std::uint8_t> encode_plane(const PifsCode& code, const PifsPlane& plane,
                                       PifsPlaneCost* cost = nullptr);

/// @brief The leaves of a plane of `width`×`height` from its bytes; InputError naming `where`
/// when the stream is truncated or holds values the header does not allow.
PifsPlane decode_plane(const PifsCode& code, int width, int height, const std::uint8_t* data,
                       std::size_t size, const std::string& where);

/// @brief Domain cells along a padded side of `padded` pixels for ranges of 2^log_size: domains
/// are 2^(log_size+1) wide on a grid of step 2^log_size (Definition 16).
inline int domain_count(int padded, int log_size) { return (padded >> log_size) - 1; }

}  // namespace ifsforge
