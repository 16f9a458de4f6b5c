#pragma once
/// @file Whole cache lines copied with streaming stores, for buffers written once and read much
/// later (the bins of tiled counting): a line written whole need not be read from memory first,
/// which a plain store does for every line it misses.
#include <cstddef>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace ifsforge {

/// @brief Copies `lines` 64-byte lines from `from` to `to` (both 16-byte aligned).
inline void stream_lines(void* to, const void* from, std::size_t lines) {
#if defined(__SSE2__)
  auto* out = static_cast<__m128i*>(to);
  const auto* in = static_cast<const __m128i*>(from);
  for (std::size_t k = 0; k < 4 * lines; ++k) _mm_stream_si128(out + k, _mm_load_si128(in + k));
#else
  std::memcpy(to, from, 64 * lines);
#endif
}

}  // namespace ifsforge
