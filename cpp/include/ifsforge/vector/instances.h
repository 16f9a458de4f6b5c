#pragma once
/// @file Vector recursive rendering (seed 5.8.2, 6.1.3.5, 6.2.3.3-6.2.3.4, 6.3.3.2, 6.5.3.2, 6.6):
/// a vector (two points q0, q1) and, in 3D, a second axis pushed through the maps to every
/// address of the recursion, normalised at the leaves (Eq. 60-62), gives an instance list:
/// where each primitive goes, how it is turned and scaled, which primitive (Eq. 99, 107) and
/// which colour (the colour channels, Eq. 101).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ifsforge/core/names.h"
#include "ifsforge/core/progress.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/vector/addresses.h"
#include "ifsforge/vector/primitives.h"

namespace ifsforge {

/// How the drawn vector's length d is set at the leaves (Eq. 60). The seed leaves the scale
/// factor sf open; both readings are offered:
///  - Proportional: d = sf |q1' - q0'|, the literal Eq. 60: every instance keeps the size of
///    its piece of the attractor (times sf).
///  - Constant: d = length for every instance, whatever the contraction along its address.
enum class Normalization { Proportional, Constant };
template <>
struct EnumNames<Normalization> {
  static constexpr const char* what = "normalization";
  static constexpr NamedValue<Normalization> values[] = {
      {Normalization::Proportional, "proportional"},
      {Normalization::Constant, "constant"}};
};

/// Where instance colours come from. Auto: Channels when the layout has colour channels
/// (gray, rgb, hsi, rgba, alpha), else FirstMap.
enum class ColorSource { Auto, Channels, FirstMap, LastMap, Constant };
template <>
struct EnumNames<ColorSource> {
  static constexpr const char* what = "color source";
  static constexpr NamedValue<ColorSource> values[] = {
      {ColorSource::Auto, "auto"},
      {ColorSource::Channels, "channels"},
      {ColorSource::FirstMap, "first-map"},
      {ColorSource::LastMap, "last-map"},
      {ColorSource::Constant, "constant"}};
};

struct InstanceOptions {
  int depth = 0;                 ///< recursion depth L (0: default_instance_depth)
  double min_probability = 0.0;  ///< pv: a branch less probable than this stops early (5.7)
  /// The primitives the index channel k chooses from (Eq. 99, 107): round(k') wrapped modulo
  /// the list length. Without a k channel every instance takes the first.
  std::vector<Primitive> primitives = {Primitive{}};
  Normalization normalization = Normalization::Proportional;
  double scale_factor = 1.0;     ///< sf of Eq. 60 (proportional)
  /// Constant: the vector length; 0 takes |q1 - q0| s^L, s the geometric mean of the (non-zero)
  /// spatial contraction factors: about the size of a piece at depth L.
  double length = 0.0;
  /// q0 in all dim() channels; empty: the centre of the attractor's bounds.
  std::vector<double> base_point;
  /// q1 - q0 in the spatial channels; empty: (R, 0[, 0]), R the half-diagonal of the spatial
  /// bounds, so an unmapped sphere of radius d = R holds the whole attractor.
  std::vector<double> base_vector;
  /// The second axis of the frame before mapping (3D: the frame's e2 comes from it; both: the
  /// fallback direction where a map collapses the vector); empty: y, or z when the base vector
  /// runs nearly along y (2D: the base vector turned by +90 degrees). Not parallel to it.
  std::vector<double> base_up;
  ColorSource color_source = ColorSource::Auto;
  /// Eq. 101: stretch each colour channel over its range on the attractor. False: take the
  /// channel values as they are (clamped to [0, 1]; hue wraps), for systems designed with
  /// colours in [0, 1].
  bool normalize_colors = true;
  std::array<float, 4> color{0.8f, 0.8f, 0.8f, 1.0f};  ///< ColorSource::Constant
  int threads = 0;                ///< 0: every core; the list never depends on it
  ProgressCallback progress;
};

/// @brief One primitive per leaf of the recursion, in address (depth-first) order.
struct InstanceList {
  std::string name;      ///< the system's
  int spatial_dims = 3;  ///< 2: the instances lie in the z = 0 plane and e3 = +z
  std::vector<Primitive> primitives;
  std::vector<std::array<float, 3>> positions;  ///< q0' = w_address(q0), spatial part (z = 0 in 2D)
  /// Rows e1, e2, e3: e1 along q1' - q0' (Eq. 61 with atan2), e2 the second axis made
  /// orthogonal (2D: e1 turned by +90 degrees), e3 = e1 x e2. Always a rotation.
  std::vector<std::array<float, 9>> frames;
  std::vector<float> scales;                    ///< d of Eq. 60: the drawn vector is q0' -> q0' + d e1
  std::vector<std::uint16_t> primitive;         ///< index into `primitives`
  std::vector<std::array<float, 4>> colors;     ///< RGBA in [0, 1], sRGB-encoded (display values)
  AddressTable addresses;

  std::size_t size() const { return scales.size(); }
  /// @brief The box holding every instance's bounding ball (scale times the primitive's
  /// bounding radius); false when no instance has a positive scale.
  bool bounds(std::array<double, 3>& lo, std::array<double, 3>& hi) const;
};

/// @brief Vector recursive rendering of `ifs` (which must have an attractor). Leaves at depth L,
/// or earlier where the address probability drops below pv. Address-prefix jobs write straight
/// into their slots, so the list is identical for any thread count. MemoryBudgetError when the
/// list would not fit; InputError for bad options, recurrent systems and condensation sets.
InstanceList instances(const Ifs& ifs, const InstanceOptions& options = {});

/// @brief The largest L with N^L <= max_instances (at least 1).
int default_instance_depth(std::size_t maps, std::uint64_t max_instances = 50000);

/// @brief Bytes one instance takes at address depth `depth` (for the memory budget).
double instance_bytes(int depth);

}  // namespace ifsforge
