// The POV-Ray writer of terrains: a height_field or mesh2 with its palette, framed for terrains
// (POV-Ray's own y-up axes, which height_field uses natively).
#include "ifsforge/io/terrain_povray.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/io/atomic_file.h"
#include "ifsforge/io/png.h"
#include "ifsforge/io/pov_palette.h"
#include "ifsforge/io/pov_text.h"
#include "ifsforge/terrain/height_image.h"
#include "ifsforge/terrain/terrain_mesh.h"

namespace ifsforge {
namespace {

class Text {
 public:
  void line(const char* format, ...) __attribute__((format(printf, 2, 3))) {
    char buffer[512];
    va_list args;
    va_start(args, format);
    std::vsnprintf(buffer, sizeof buffer, format, args);
    va_end(args);
    text_ += buffer;
    text_ += '\n';
  }
  void raw(const std::string& s) { text_ += s; }
  const std::string& str() const { return text_; }

 private:
  std::string text_;
};

/// `stem` as a portable file name part: ASCII letters, digits, '.', '-' and '_' (others become
/// '_'), so the scene names its height PNG by a plain string POV-Ray finds.
std::string file_stem(const std::string& stem) {
  std::string out = ascii_text(stem, '_');
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-') c = '_';
  return out.empty() || out[0] == '.' ? "terrain" + out : out;
}

}  // namespace

std::vector<std::string> write_terrain_pov(const std::string& path, const Terrain& t, const Palette& palette,
                                           const TerrainPovOptions& o, int threads) {
  if (!(o.aspect > 0 && std::isfinite(o.aspect))) throw InputError("POV-Ray terrain: the aspect must be positive");
  check_writable(path);

  const std::array<double, 4> box = t.extent();
  const double sx = box[2] - box[0], sy = box[3] - box[1], span = std::max(sx, sy);
  const double lo = t.min_height, hi = t.max_height, range = std::max(hi - lo, 1e-9 * span);
  Palette colours = palette;
  if (colours.colors.empty()) colours.colors = {{0.2f, 0.2f, 0.2f}, {0.95f, 0.95f, 0.95f}};

  Text s;
  s.raw("// " + pov_comment(o.title) + "\n");
  s.line("// ifsforge terrain: %s grid, %d x %d samples, heights %.6g to %.6g.", name_of(t.grid), t.columns, t.rows,
         lo, hi);
  s.line("// Axes: x east, y up, z north. Render: povray +I<this file> +O<image>.png +W<w> +H<h> +A");
  s.line("#version 3.7;");
  s.line("global_settings { assumed_gamma 1.0 }");
  s.raw("#declare IFS_Title = " + pov_string(o.title) + ";\n");
  const std::string color_map = pov_identifier("Palette", o.palette_name);
  s.raw("#declare " + color_map + " = " + pov_color_map(colours) + "\n");
  if (o.camera == TerrainPovCamera::Top) {
    s.line("camera { orthographic location <%.9g, %.9g, %.9g> direction <0, -1, 0>", 0.5 * (box[0] + box[2]),
           hi + range + span, 0.5 * (box[1] + box[3]));
    s.line("  up <0, 0, %.9g> right <%.9g, 0, 0> }", sy, sx);
  } else {
    const double distance = 1.25 * std::max(span, 1.5 * range), elevation = 35.0 * M_PI / 180.0, target = lo + 0.3 * range;
    s.line("camera { perspective location <%.9g, %.9g, %.9g> look_at <0, %.9g, 0>", -0.55 * distance,
           target + distance * std::sin(elevation), -0.85 * distance, target);
    s.line("  right x*%.9g angle 50 }", o.aspect);
  }
  std::string finish = "finish { ambient 1 diffuse 0 }";
  if (!o.flat) {
    s.line("light_source { <-0.6, 1.0, -0.4>*%.9g color srgb <1.0, 0.96, 0.88> parallel point_at <0, 0, 0> }",
           10.0 * span);
    s.line("sky_sphere { pigment { gradient y color_map { [0 srgb <0.80, 0.88, 1.0>] [1 srgb <0.36, 0.56, 0.90>] } } }");
    finish = "finish { ambient 0.18 diffuse 0.82 }";
  }

  std::vector<std::string> written;
  if (o.shape == TerrainPovShape::HeightField) {
    // POV-Ray maps the image onto the unit square: column -> x, row 0 -> z = 1 (north), gray -> y.
    const std::filesystem::path scene(path);
    const std::string png_name = file_stem(scene.stem().string()) + "_height.png";
    const std::string png_path = (scene.parent_path() / png_name).string();
    write_png(png_path, height_image(t, 0, 0, threads), 16);
    written.push_back(png_path);
    s.line("height_field { png %s smooth", pov_string(png_name).c_str());
    // The pigment lives in the unit square, before the scale: gradient y spans [0, 1) there;
    // 1.0001 keeps the highest point from wrapping round to the lowest colour.
    s.line("  pigment { gradient y color_map { %s } scale <1, 1.0001, 1> }", color_map.c_str());
    s.line("  %s", finish.c_str());
    s.line("  scale <%.9g, %.9g, %.9g> translate <%.9g, %.9g, %.9g> }", sx, range, sy, box[0], lo, box[1]);
  } else {
    const TriangleMesh mesh = terrain_mesh(t, {}, threads);
    s.line("mesh2 {");
    s.line("  vertex_vectors { %zu,", mesh.positions.size());
    for (const auto& p : mesh.positions) s.line("    <%.7g, %.7g, %.7g>,", p[0], p[2], p[1]);
    s.line("  }");
    s.line("  normal_vectors { %zu,", mesh.normals.size());
    for (const auto& n : mesh.normals) s.line("    <%.6f, %.6f, %.6f>,", n[0], n[2], n[1]);
    s.line("  }");
    s.line("  face_indices { %zu,", mesh.triangles.size());
    for (const auto& f : mesh.triangles) s.line("    <%u, %u, %u>,", f[0], f[1], f[2]);
    s.line("  }");
    s.line("  pigment { gradient y color_map { %s } scale <1, %.9g, 1> translate <0, %.9g, 0> }",
           color_map.c_str(), range * 1.0001, lo);
    s.line("  %s", finish.c_str());
    s.line("}");
  }
  AtomicFile file(path);
  if (std::fwrite(s.str().data(), 1, s.str().size(), file.file()) != s.str().size())
    throw FileError("cannot write '" + path + "'");
  file.commit();
  written.insert(written.begin(), path);
  return written;
}

}  // namespace ifsforge
