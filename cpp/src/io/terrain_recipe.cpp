#include "ifsforge/io/terrain_recipe.h"

#include <filesystem>

#include "ifsforge/io/text_file.h"
#include "ifsforge/io/png.h"
#include "ifsforge/terrain/terrain_controls.h"
#include "ifsforge/interpolation/vertical_scaling.h"
#include "json_reader.h"

namespace ifsforge {
namespace {

using detail::json;
using detail::JsonReader;

std::string resolve(const std::string& folder, const std::string& name) {
  const std::filesystem::path p(name);
  return p.is_absolute() ? name : (std::filesystem::path(folder) / p).string();
}

void read_heights(const JsonReader& r, const json& j, TerrainControls& c, const std::string& folder) {
  if (j.is_array()) {
    c.heights = r.matrix(j, "/heights");
    return;
  }
  r.only(j, "/heights", {"random", "map"});
  if (j.contains("random") == j.contains("map")) r.fail("/heights", "give rows of heights, or \"random\", or \"map\"");
  if (j.contains("random")) {
    const json& g = j["random"];
    const std::string p = "/heights/random";
    r.only(g, p, {"rows", "columns", "base", "amplitude", "seed"});
    for (const char* k : {"rows", "columns"})
      if (!g.contains(k)) r.fail(p + "/" + k, "missing");
    const int rows = r.integer(g["rows"], p + "/rows", 2, 4096), columns = r.integer(g["columns"], p + "/columns", 2, 4096);
    std::vector<double> base = {0.5};
    if (g.contains("base")) base = g["base"].is_array() ? r.numbers(g["base"], p + "/base") : std::vector<double>{r.number(g["base"], p + "/base")};
    const double amplitude = g.contains("amplitude") ? r.number(g["amplitude"], p + "/amplitude") : 0.5;
    const std::uint64_t seed = g.contains("seed") ? r.seed(g["seed"], p + "/seed") : 0;
    c.heights = r.at(p, [&] { return random_heights(c.grid, rows, columns, base, amplitude, seed); });
    return;
  }
  const json& m = j["map"];
  const std::string p = "/heights/map";
  r.only(m, p, {"file", "rows", "columns", "window", "low", "high"});
  for (const char* k : {"file", "rows", "columns"})
    if (!m.contains(k)) r.fail(p + "/" + k, "missing");
  const int rows = r.integer(m["rows"], p + "/rows", 2, 4096), columns = r.integer(m["columns"], p + "/columns", 2, 4096);
  std::array<double, 4> window = {0, 0, 1, 1};
  if (m.contains("window")) {
    const std::vector<double> w = r.numbers(m["window"], p + "/window", 4);
    std::copy(w.begin(), w.end(), window.begin());
  }
  const double low = m.contains("low") ? r.number(m["low"], p + "/low") : 0.0;
  const double high = m.contains("high") ? r.number(m["high"], p + "/high") : 1.0;
  const std::string file = resolve(folder, r.text(m["file"], p + "/file"));
  const Image image = r.at(p + "/file", [&] { return read_png(file); });
  r.at(p, [&] {
    sample_heights(c, rows, columns, image, window, low, high);
    return 0;
  });
}

std::vector<double> read_roughness(const JsonReader& r, const json& j, const std::string& path, std::size_t maps,
                                   SignPattern signs, std::uint64_t seed, std::uint64_t stream) {
  if (j.is_array()) {
    std::vector<double> a22 = r.numbers(j, path);
    r.at(path, [&] {
      check_vertical_scaling(a22, "a22");
      return 0;
    });
    return a22;
  }
  const double roughness = r.number(j, path);
  return r.at(path, [&] { return vertical_scaling(maps, roughness, signs, seed, stream); });
}

}  // namespace

TerrainRecipe parse_terrain_recipe(const std::string& text, const std::string& source, const std::string& folder) {
  const JsonReader r(source);
  const json j = r.document(text, "ifsforge-terrain/1");
  r.only(j, "", {"format", "name", "description", "grid", "heights", "radii", "shift", "roughness", "size",
                 "resolution", "palette"});
  TerrainRecipe recipe;
  TerrainControls& c = recipe.controls;
  if (j.contains("name")) recipe.name = r.text(j["name"], "/name");
  if (j.contains("description")) recipe.description = r.text(j["description"], "/description");
  if (!j.contains("grid")) r.fail("/grid", "missing: regular, irregular or circular");
  c.grid = r.at("/grid", [&] { return parse_name<TerrainGrid>(r.text(j["grid"], "/grid")); });
  // The radii come first: heights sampled from a map need them on a circular grid.
  if (j.contains("radii")) c.radii = r.numbers(j["radii"], "/radii");
  if (j.contains("shift") && j["shift"].is_object() && !j["shift"].contains("random")) {
    r.only(j["shift"], "/shift", {"u", "v"});
    if (j["shift"].contains("u")) c.shift_u = r.matrix(j["shift"]["u"], "/shift/u");
    if (j["shift"].contains("v")) c.shift_v = r.matrix(j["shift"]["v"], "/shift/v");
  }
  if (!j.contains("heights")) r.fail("/heights", "missing: rows of control heights, \"random\" or \"map\"");
  read_heights(r, j["heights"], c, folder);
  if (j.contains("shift")) {
    const json& s = j["shift"];
    if (!s.is_object()) r.fail("/shift", "expected an object with \"u\" and \"v\", or \"random\"");
    if (s.contains("random")) {
      r.only(s, "/shift", {"random"});
      r.only(s["random"], "/shift/random", {"amplitude", "seed"});
      if (!s["random"].contains("amplitude")) r.fail("/shift/random/amplitude", "missing");
      const double amplitude = r.number(s["random"]["amplitude"], "/shift/random/amplitude");
      const std::uint64_t seed = s["random"].contains("seed") ? r.seed(s["random"]["seed"], "/shift/random/seed") : 0;
      r.at("/shift/random", [&] {
        random_shifts(c, amplitude, seed);
        return 0;
      });
    }
  }
  const std::size_t rows = c.heights.size(), columns = c.heights[0].size();
  const std::size_t maps_u = c.grid == TerrainGrid::Circular ? columns : columns - 1;
  if (j.contains("roughness")) {
    const json& g = j["roughness"];
    r.only(g, "/roughness", {"u", "v", "shift", "signs", "seed"});
    SignPattern signs = SignPattern::Random;
    if (g.contains("signs")) signs = r.at("/roughness/signs", [&] { return parse_name<SignPattern>(r.text(g["signs"], "/roughness/signs")); });
    const std::uint64_t seed = g.contains("seed") ? r.seed(g["seed"], "/roughness/seed") : 0;
    if (g.contains("u")) c.a22_u = read_roughness(r, g["u"], "/roughness/u", maps_u, signs, seed, 1);
    if (g.contains("v")) c.a22_v = read_roughness(r, g["v"], "/roughness/v", rows - 1, signs, seed, 2);
    if (g.contains("shift")) c.a22_shift = read_roughness(r, g["shift"], "/roughness/shift", maps_u, signs, seed, 3);
  }
  if (j.contains("size")) {
    const std::vector<double> s = r.numbers(j["size"], "/size", 2);
    c.size_x = s[0];
    c.size_y = s[1];
  }
  if (j.contains("resolution")) {
    const json& res = j["resolution"];
    if (!res.is_array() || res.size() != 2) r.fail("/resolution", "expected [columns, rows]");
    recipe.columns = r.integer(res[0], "/resolution/0", 3, 65535);
    recipe.rows = r.integer(res[1], "/resolution/1", 2, 65535);
  }
  if (j.contains("palette")) {
    const json& p = j["palette"];
    if (p.is_string()) {
      const std::string file = resolve(folder, p.get<std::string>());
      try {
        recipe.palette = read_palette_recipe(file);
      } catch (const FileError& e) {
        r.fail("/palette", e.what());
      }
    } else if (p.is_object()) {
      recipe.palette = parse_palette_recipe(p.dump(), source + ": /palette");
    } else {
      r.fail("/palette", "expected a palette recipe file name or an inline palette recipe");
    }
  }
  // Everything make_terrain checks (counts, displacements, radii), reported against the file.
  r.at("", [&] { return make_terrain(c, 3, 2, 1); });
  return recipe;
}

TerrainRecipe read_terrain_recipe(const std::string& path) {
  const std::string folder = std::filesystem::path(path).parent_path().string();
  return parse_terrain_recipe(read_text_file(path), path, folder.empty() ? "." : folder);
}

}  // namespace ifsforge
