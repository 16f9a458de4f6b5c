#include "ifsforge/io/pov_palette.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/io/pov_text.h"

namespace ifsforge {

std::string pov_color_map(const Palette& palette, std::size_t entries, bool linear) {
  if (palette.colors.empty()) throw InputError("the palette is empty");
  entries = std::clamp<std::size_t>(std::min(entries, palette.size()), 2, 256);
  // The sRGB decoding (IEC 61966-2-1), for the linear form.
  auto decode = [](double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); };
  std::ostringstream s;
  s << "color_map {\n";
  char line[128];
  for (std::size_t k = 0; k < entries; ++k) {
    const double t = double(k) / double(entries - 1);
    const std::array<float, 3> c = palette.lookup(t);
    if (linear)
      std::snprintf(line, sizeof line, "  [%.6f rgb <%.7f, %.7f, %.7f>]\n", t, decode(c[0]), decode(c[1]), decode(c[2]));
    else
      std::snprintf(line, sizeof line, "  [%.6f srgb <%.6f, %.6f, %.6f>]\n", t, c[0], c[1], c[2]);
    s << line;
  }
  s << "}";
  return s.str();
}

std::string pov_palette_include(const Palette& palette, const std::string& name, const std::string& about,
                                std::size_t entries) {
  return "// ifsforge fractal palette " + pov_comment(name) + "\n" + pov_comment_lines(about) +
         "// Colors as linear rgb (exact under assumed_gamma 1.0): this file parses before or without\n"
         "// any assumed_gamma. Use: pigment { gradient y color_map { " + pov_identifier("Palette", name) + " } }\n" +
         "#declare " + pov_identifier("Palette", name) + " = " + pov_color_map(palette, entries, true) + "\n";
}

}  // namespace ifsforge
