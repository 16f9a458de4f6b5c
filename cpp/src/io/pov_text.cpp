// Input text made safe for POV-Ray 3.7 scene language (comments, strings, identifiers).
#include "ifsforge/io/pov_text.h"

#include <algorithm>
#include <stdexcept>

namespace ifsforge {
namespace {

/// The next code point of UTF-8 `text` from `i` (advanced past it), or -1 for a byte that does
/// not start a valid, shortest-form sequence (then `i` moves one byte).
long next_code_point(const std::string& text, std::size_t& i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = byte(i);
  if (c < 0x80) return ++i, c;
  const int length = c >= 0xF0 && c <= 0xF4 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 && c < 0xE0 ? 2 : 0;
  if (length == 0 || c > 0xF4 || i + length > text.size()) return ++i, -1;
  long cp = c & (0x7F >> length);
  for (int k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return ++i, -1;
    cp = (cp << 6) | (byte(i + k) & 0x3F);
  }
  const long least[5] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < least[length] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return ++i, -1;
  i += length;
  return cp;
}

// Latin-1 Supplement letters U+00C0..U+00FF and Latin Extended-A U+0100..U+017F without their
// accents; '*' marks the letters written with two (kTwoLetters), '_' a sign with no letter.
const char kLatin1[] = "AAAAAA*CEEEEIIIIDNOOOOOxOUUUUY**aaaaaa*ceeeeiiiidnooooo_ouuuuy*y";
const char kLatinA[] =
    "AaAaAaCcCcCcCcDdDdEeEeEeEeEeGgGgGgGgHhHhIiIiIiIiIi**JjKkkLlLlLlLlLlNnNnNnnNnOoOoOo**RrRrRrSsSsSsSsTtTtTtUuUuUuUuUuUu"
    "WwYyYZzZzZzs";
static_assert(sizeof kLatin1 == 64 + 1 && sizeof kLatinA == 128 + 1, "one letter per code point");

const char* two_letters(long cp) {
  switch (cp) {
    case 0xC6: return "AE";
    case 0xDE: return "Th";
    case 0xDF: return "ss";
    case 0xE6: return "ae";
    case 0xFE: return "th";
    case 0x132: return "IJ";
    case 0x133: return "ij";
    case 0x152: return "OE";
    case 0x153: return "oe";
  }
  return "?";
}

/// The ASCII form of one code point, or nullptr when it has none.
const char* ascii_of(long cp, char (&one)[2]) {
  char c = 0;
  if (cp >= 0x20 && cp < 0x7F) c = static_cast<char>(cp);
  else if (cp < 0x20 || cp == 0x7F || (cp >= 0x80 && cp < 0xA0) || cp == 0x2028 || cp == 0x2029) c = ' ';
  else if (cp >= 0xC0 && cp < 0x100) c = kLatin1[cp - 0xC0];
  else if (cp >= 0x100 && cp < 0x180) c = kLatinA[cp - 0x100];
  else if (cp == 0xA0 || (cp >= 0x2000 && cp <= 0x200A) || cp == 0x202F || cp == 0x3000) c = ' ';
  else if (cp >= 0x2010 && cp <= 0x2015) c = '-';
  else if (cp == 0x2018 || cp == 0x2019 || cp == 0x201A || cp == 0x2032) c = '\'';
  else if (cp == 0x201C || cp == 0x201D || cp == 0x201E || cp == 0x2033) c = '"';
  if (c == '*' && cp >= 0xC0) return two_letters(cp);
  if (c == 0 || (c == '_' && cp >= 0xC0)) return nullptr;
  one[0] = c;
  one[1] = 0;
  return one;
}

bool letter_or_digit(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'); }

// POV-Ray 3.7's reserved words: its keywords, directives and built-in identifiers (the
// reference's "Reserved Keywords" and the parser's token table), sorted for binary search.
const char* const kReserved[] = {
    "aa_level", "aa_threshold", "abs", "absorption", "accuracy", "acos", "acosh", "adaptive", "adc_bailout",
    "agate", "agate_turb", "albedo", "all", "all_intersections", "alpha", "altitude", "always_sample", "ambient",
    "ambient_light", "angle", "aoi", "aperture", "append", "arc_angle", "area_illumination", "area_light", "array",
    "asc", "ascii", "asin", "asinh", "assumed_gamma", "atan", "atan2", "atanh", "autostop", "average", "b_spline",
    "background", "bezier_spline", "bicubic_patch", "bitwise_and", "bitwise_or", "bitwise_xor", "black_hole",
    "blob", "blue", "blur_samples", "bmp", "bokeh", "bounded_by", "box", "boxed", "bozo", "break", "brick",
    "brick_size", "brightness", "brilliance", "bump_map", "bump_size", "bumps", "camera", "case", "caustics",
    "ceil", "cells", "charset", "checker", "chr", "circular", "clipped_by", "clock", "clock_delta", "clock_on",
    "collect", "color", "color_map", "colour", "colour_map", "component", "composite", "concat", "cone",
    "confidence", "conic_sweep", "conserve_energy", "contained_by", "control0", "control1", "coords", "cos",
    "cosh", "count", "crackle", "crand", "cube", "cubic", "cubic_spline", "cubic_wave", "cutaway_textures",
    "cylinder", "cylindrical", "datetime", "debug", "declare", "default", "defined", "degrees", "density",
    "density_file", "density_map", "dents", "deprecated", "df3", "difference", "diffuse", "dimension_size",
    "dimensions", "direction", "disc", "dispersion", "dispersion_samples", "dist_exp", "distance", "div",
    "double_illuminate", "eccentricity", "else", "elseif", "emission", "end", "error", "error_bound", "evaluate",
    "exp", "expand_thresholds", "exponent", "exr", "exterior", "extinction", "face_indices", "facets",
    "fade_color", "fade_colour", "fade_distance", "fade_power", "falloff", "falloff_angle", "false", "fclose",
    "file_exists", "filter", "final_clock", "final_frame", "finish", "fisheye", "flatness", "flip", "floor",
    "focal_point", "fog", "fog_alt", "fog_offset", "fog_type", "fopen", "for", "form", "frame_number",
    "frequency", "fresnel", "function", "gamma", "gather", "gif", "global_lights", "global_settings", "gradient",
    "granite", "gray", "gray_threshold", "green", "hdr", "height_field", "hexagon", "hf_gray_16", "hierarchy",
    "hollow", "hypercomplex", "if", "ifdef", "iff", "ifndef", "image_height", "image_map", "image_pattern",
    "image_width", "importance", "include", "initial_clock", "initial_frame", "input_file_name", "inside",
    "inside_vector", "int", "interior", "interior_texture", "internal", "interpolate", "intersection",
    "intervals", "inverse", "ior", "irid", "irid_wavelength", "isosurface", "jitter", "jpeg", "julia",
    "julia_fractal", "lambda", "lathe", "leopard", "light_group", "light_source", "linear_spline",
    "linear_sweep", "ln", "load_file", "local", "location", "log", "look_at", "looks_like", "low_error_factor",
    "macro", "magnet", "major_radius", "mandel", "map_type", "marble", "material", "material_map", "matrix",
    "max", "max_extent", "max_gradient", "max_intersections", "max_iteration", "max_sample", "max_trace",
    "max_trace_level", "maximum_reuse", "media", "media_attenuation", "media_interaction", "merge", "mesh",
    "mesh2", "mesh_camera", "metallic", "method", "metric", "min", "min_extent", "minimum_reuse", "mm_per_unit",
    "mod", "mortar", "natural_spline", "nearest_count", "no", "no_bump_scale", "no_image", "no_radiosity",
    "no_reflection", "no_shadow", "noise_generator", "normal", "normal_indices", "normal_map", "normal_vectors",
    "now", "number_of_sides", "number_of_tiles", "number_of_waves", "object", "octaves", "off", "offset",
    "omega", "omnimax", "on", "once", "onion", "open", "orient", "orientation", "orthographic", "ovus",
    "panoramic", "parallel", "parametric", "pass_through", "pattern", "pavement", "perspective", "pgm", "phase",
    "phong", "phong_size", "photons", "pi", "pigment", "pigment_map", "pigment_pattern", "planar", "plane",
    "png", "point_at", "poly", "poly_wave", "polygon", "polynomial", "pot", "pow", "ppm", "precision",
    "precompute", "premultiplied", "pretrace_end", "pretrace_start", "prism", "prod", "projected_through",
    "pwr", "quadratic_spline", "quadric", "quartic", "quaternion", "quick_color", "quick_colour", "quilted",
    "radial", "radians", "radiosity", "radius", "rainbow", "ramp_wave", "rand", "range", "ratio", "read",
    "reciprocal", "recursion_limit", "red", "reflection", "reflection_exponent", "refraction", "render",
    "repeat", "rgb", "rgbf", "rgbft", "rgbt", "right", "ripples", "rotate", "roughness", "samples", "save_file",
    "scale", "scallop_wave", "scattering", "seed", "select", "shadowless", "sin", "sine_wave", "sinh",
    "sint16be", "sint16le", "sint32be", "sint32le", "sint8", "size", "sky", "sky_sphere", "slice", "slope",
    "slope_map", "smooth", "smooth_triangle", "solid", "sor", "spacing", "specular", "sphere", "sphere_sweep",
    "spherical", "spiral1", "spiral2", "spline", "split_union", "spotlight", "spotted", "sqr", "sqrt", "srgb",
    "srgbf", "srgbft", "srgbt", "statistics", "str", "strcmp", "strength", "strlen", "strlwr", "strupr", "sturm",
    "substr", "subsurface", "sum", "superellipsoid", "switch", "sys", "t", "tan", "tanh", "target", "tau",
    "text", "texture", "texture_list", "texture_map", "tga", "thickness", "threshold", "tiff", "tightness",
    "tile2", "tiles", "tiling", "tolerance", "toroidal", "torus", "trace", "transform", "translate",
    "translucency", "transmit", "triangle", "triangle_wave", "triangular", "true", "ttf", "turb_depth",
    "turbulence", "type", "u", "u_steps", "uint16be", "uint16le", "uint8", "ultra_wide_angle", "undef",
    "union", "up", "use_alpha", "use_color", "use_colour", "use_index", "utf8", "uv", "uv_indices", "uv_mapping",
    "uv_vectors", "v", "v_steps", "val", "variance", "vaxis_rotate", "vcross", "vdot", "version",
    "vertex_vectors", "vlength", "vnormalize", "vrotate", "vstr", "vturbulence", "warning", "warp",
    "water_level", "waves", "while", "width", "wood", "wrinkles", "write", "x", "xyz", "y", "yes", "z"};

}  // namespace

std::string ascii_text(const std::string& text, char unknown) {
  std::string out;
  out.reserve(text.size());
  char one[2];
  for (std::size_t i = 0; i < text.size();) {
    const long cp = next_code_point(text, i);
    const char* ascii = cp < 0 ? nullptr : ascii_of(cp, one);
    if (ascii) out += ascii;
    else out += unknown;
  }
  return out;
}

std::string pov_comment(const std::string& text) {
  const std::string ascii = ascii_text(text);
  std::string out;
  for (std::size_t i = 0; i < ascii.size(); ++i) {
    const char c = ascii[i];
    if (c == '#') {
      out += "No.";
    } else if ((c == '/' || c == '*') && i + 1 < ascii.size() && ascii[i + 1] == (c == '/' ? '*' : '/')) {
      out += c;
      out += ' ';
    } else {
      out += c;
    }
  }
  return out;
}

std::string pov_comment_lines(const std::string& text) {
  std::string out;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    out += "// " + pov_comment(text.substr(start, end - start)) + "\n";
    start = end + 1;
  }
  return out;
}

std::string pov_string(const std::string& text) {
  std::string out = "\"";
  for (const char c : ascii_text(text)) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string pov_name(const std::string& name) {
  constexpr std::size_t kMaxName = 48;
  std::string out;
  for (const char c : ascii_text(name, '_')) {
    if (letter_or_digit(c)) {
      if (out.size() >= kMaxName) break;
      out += c;
    } else if (!out.empty() && out.back() != '_') {
      out += '_';
    }
  }
  while (!out.empty() && out.back() == '_') out.pop_back();
  return out;
}

std::string pov_identifier(const std::string& kind, const std::string& name) {
  bool valid = !kind.empty() && kind[0] >= 'A' && kind[0] <= 'Z';
  for (const char c : kind) valid = valid && letter_or_digit(c);
  if (!valid) throw std::invalid_argument("POV-Ray identifier kind '" + kind + "' is not a capitalised ASCII word");
  const std::string part = pov_name(name);
  return "IFS_" + kind + (part.empty() ? "" : "_" + part);
}

std::string xml_text(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t start = i;
    const long cp = next_code_point(text, i);
    switch (cp) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        if (cp < 0 || cp == 0xFFFE || cp == 0xFFFF) out += "\xEF\xBF\xBD";  // U+FFFD
        else if (cp < 0x20 && cp != '\t' && cp != '\n') out += ' ';
        else out.append(text, start, i - start);
    }
  }
  return out;
}

const std::vector<std::string_view>& pov_reserved_words() {
  static const std::vector<std::string_view> words(std::begin(kReserved), std::end(kReserved));
  return words;
}

bool pov_reserved_word(std::string_view word) {
  const auto& words = pov_reserved_words();
  return std::binary_search(words.begin(), words.end(), word);
}

PovNames::PovNames(std::vector<std::string> reserved) : used_(reserved.begin(), reserved.end()) {}

std::string PovNames::take(const std::string& kind, const std::string& name) {
  const std::string base = pov_identifier(kind, name);
  std::string identifier = base;
  for (int k = 2; used_.count(identifier); ++k) identifier = base + "_" + std::to_string(k);
  used_.insert(identifier);
  return identifier;
}

}  // namespace ifsforge
