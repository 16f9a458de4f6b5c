#pragma once
/// @file What each dimension of an nD IFS means (seed 3.2 and chapter 6).
#include <string>
#include <vector>

namespace ifsforge {

/// @brief How the extra (non-spatial) channels are interpreted.
enum class ColorModel { None, Gray, Rgb, Hsi, Rgba };

/// @brief A layout such as "xy", "xyz+rgb", "xy+hsi", "xyz+gray", "xy+rgba", "xyz+rgb+k".
/// Spatial part "xy" or "xyz", then '+'-separated groups: gray, alpha, rgb, hsi, rgba, k.
class ChannelLayout {
 public:
  ChannelLayout() : ChannelLayout("xy") {}
  explicit ChannelLayout(const std::string& text);

  const std::string& text() const { return text_; }
  int dim() const { return static_cast<int>(names_.size()); }
  int spatial_dims() const { return spatial_; }
  const std::vector<std::string>& names() const { return names_; }
  /// @brief Index of channel `name` ("x", "r", "h", "gray", "alpha", "k"...), or -1.
  int index(const std::string& name) const;
  ColorModel color_model() const { return color_; }
  /// @brief First index of the colour channels (gray, rgb, hsi or rgba), or -1.
  int color_index() const { return color_index_; }
  int alpha_index() const { return index("alpha"); }
  int primitive_index() const { return index("k"); }

  bool operator==(const ChannelLayout& o) const { return text_ == o.text_; }

 private:
  std::string text_;
  std::vector<std::string> names_;
  int spatial_ = 2;
  ColorModel color_ = ColorModel::None;
  int color_index_ = -1;
};

}  // namespace ifsforge
