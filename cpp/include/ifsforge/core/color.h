#pragma once
/// @file The one colour rule. Colour channels everywhere in ifsforge are display values:
/// sRGB-encoded, in [0, 1] (after the Eq. 101 normalization). A writer whose reader expects
/// linear light (glTF COLOR_0 and baseColorFactor, the OpenVDB "color" grid that Blender's
/// Principled Volume reads, Blender colour attributes) converts with srgb_to_linear; PNG, PLY
/// vertex colours and POV-Ray `srgb` take the display values as they are.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace ifsforge {

/// @brief The sRGB decoding (IEC 61966-2-1) of a display value, clamped to [0, 1] first. In the
/// precision of its argument: float for grids and vertex colours (powf is twice as fast as pow,
/// and a .vdb of millions of voxels converts every one), double elsewhere.
template <typename T>
inline T srgb_to_linear(T c) {
  static_assert(std::is_floating_point_v<T>, "srgb_to_linear takes float or double");
  c = std::clamp(c, T(0), T(1));
  return c <= T(0.04045) ? c / T(12.92) : std::pow((c + T(0.055)) / T(1.055), T(2.4));
}

/// srgb_to_linear<float> that remembers: each display value's power is computed once, then looked
/// up, so the result is srgb_to_linear's to the bit (a table over a grid of values could not be:
/// the display values are means, not codes). A volume's colours repeat (the voxels of one address
/// share one), and the power is most of a colour grid's cost. One per thread, kept from band to
/// band: its 2 MB hold a volume's distinct values with few collisions.
class LinearColors {
 public:
  float operator()(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    if (!(c > 0.04045f)) return srgb_to_linear(c);
    std::uint32_t bits;
    std::memcpy(&bits, &c, sizeof bits);
    // Direct-mapped; a slot holds the display value's bits above its linear value's. Key 0 (0.0f)
    // never gets here, so the empty slots match nothing.
    std::uint64_t& slot = slots_[(bits * 0x9E3779B1u) >> (32 - kBits)];
    float linear;
    if (slot >> 32 == bits) {
      const std::uint32_t value = static_cast<std::uint32_t>(slot);
      std::memcpy(&linear, &value, sizeof linear);
      return linear;
    }
    linear = srgb_to_linear(c);
    std::uint32_t value;
    std::memcpy(&value, &linear, sizeof value);
    slot = std::uint64_t(bits) << 32 | value;
    return linear;
  }

 private:
  static constexpr int kBits = 18;
  std::vector<std::uint64_t> slots_ = std::vector<std::uint64_t>(std::size_t(1) << kBits, 0);
};

/// @brief The sRGB encoding, inverse of srgb_to_linear on [0, 1].
inline double linear_to_srgb(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? c * 12.92 : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

}  // namespace ifsforge
