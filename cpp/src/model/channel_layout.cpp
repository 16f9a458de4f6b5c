#include "ifsforge/model/channel_layout.h"

#include <algorithm>

#include "ifsforge/core/error.h"
#include "ifsforge/model/affine_map.h"

namespace ifsforge {

ChannelLayout::ChannelLayout(const std::string& text) : text_(text) {
  std::vector<std::string> groups;
  std::size_t start = 0;
  for (;;) {
    const std::size_t plus = text.find('+', start);
    groups.push_back(text.substr(start, plus == std::string::npos ? std::string::npos : plus - start));
    if (plus == std::string::npos) break;
    start = plus + 1;
  }
  const std::string bad = "unknown channel layout '" + text + "': ";
  if (groups[0] == "xy") {
    names_ = {"x", "y"};
  } else if (groups[0] == "xyz") {
    names_ = {"x", "y", "z"};
  } else {
    throw InputError(bad + "it must start with xy or xyz (e.g. xy, xyz+rgb, xy+hsi, xyz+rgb+k)");
  }
  spatial_ = dim();
  auto set_color = [&](ColorModel model) {
    if (color_ != ColorModel::None) throw InputError(bad + "more than one color group");
    color_ = model;
    color_index_ = dim();
  };
  for (std::size_t g = 1; g < groups.size(); ++g) {
    const std::string& group = groups[g];
    if (group == "gray") {
      set_color(ColorModel::Gray);
      names_.push_back("gray");
    } else if (group == "rgb") {
      set_color(ColorModel::Rgb);
      names_.insert(names_.end(), {"r", "g", "b"});
    } else if (group == "hsi") {
      set_color(ColorModel::Hsi);
      names_.insert(names_.end(), {"h", "s", "i"});
    } else if (group == "rgba") {
      set_color(ColorModel::Rgba);
      names_.insert(names_.end(), {"r", "g", "b", "alpha"});
    } else if (group == "alpha" || group == "k") {
      names_.push_back(group);
    } else {
      throw InputError(bad + "'" + group + "' is not one of gray, alpha, rgb, hsi, rgba, k");
    }
  }
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (std::count(names_.begin(), names_.end(), names_[i]) > 1)
      throw InputError(bad + "channel '" + names_[i] + "' appears twice");
  if (dim() > kMaxDim)
    throw InputError(bad + "more than " + std::to_string(kMaxDim) + " dimensions");
}

int ChannelLayout::index(const std::string& name) const {
  const auto it = std::find(names_.begin(), names_.end(), name);
  return it == names_.end() ? -1 : static_cast<int>(it - names_.begin());
}

}  // namespace ifsforge
