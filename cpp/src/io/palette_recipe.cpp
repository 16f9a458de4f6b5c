#include "ifsforge/io/palette_recipe.h"

#include "json_reader.h"
#include "ifsforge/io/text_file.h"
#include "ifsforge/interpolation/vertical_scaling.h"

namespace ifsforge {

PaletteRecipe parse_palette_recipe(const std::string& text, const std::string& source) {
  const detail::JsonReader r(source);
  const detail::json j = r.document(text, "ifsforge-palette/1");
  r.only(j, "", {"format", "name", "description", "space", "stops", "positions", "roughness", "entries"});
  PaletteRecipe recipe;
  if (j.contains("name")) recipe.name = r.text(j["name"], "/name");
  if (j.contains("description")) recipe.description = r.text(j["description"], "/description");
  if (j.contains("space")) {
    try {
      recipe.spec.space = parse_name<ColorSpace>(r.text(j["space"], "/space"));
    } catch (const InputError& e) {
      r.fail("/space", e.what());
    }
  }
  if (!j.contains("stops")) r.fail("/stops", "missing: a palette needs at least 3 color stops");
  const detail::json& stops = j["stops"];
  if (!stops.is_array() || stops.size() < 3) r.fail("/stops", "expected an array of at least 3 color stops");
  for (std::size_t k = 0; k < stops.size(); ++k) {
    const std::vector<double> c = r.numbers(stops[k], "/stops/" + std::to_string(k), 3);
    recipe.spec.stops.push_back({c[0], c[1], c[2]});
  }
  if (j.contains("positions")) recipe.spec.positions = r.numbers(j["positions"], "/positions", stops.size());
  if (j.contains("entries")) recipe.entries = std::size_t(r.integer(j["entries"], "/entries", 2, 1 << 24));
  if (j.contains("roughness")) {
    const detail::json& rough = j["roughness"];
    r.only(rough, "/roughness", {"components", "signs", "seed"});
    SignPattern signs = SignPattern::Random;
    std::uint64_t seed = 0;
    if (rough.contains("signs")) {
      try {
        signs = parse_name<SignPattern>(r.text(rough["signs"], "/roughness/signs"));
      } catch (const InputError& e) {
        r.fail("/roughness/signs", e.what());
      }
    }
    if (rough.contains("seed")) seed = r.seed(rough["seed"], "/roughness/seed");
    if (!rough.contains("components")) r.fail("/roughness/components", "missing: one roughness per color component");
    const detail::json& comps = rough["components"];
    if (!comps.is_array() || comps.size() != 3)
      r.fail("/roughness/components", "expected 3 entries (one per color component), found " + r.describe(comps));
    for (int c = 0; c < 3; ++c) {
      const std::string path = "/roughness/components/" + std::to_string(c);
      try {
        if (comps[c].is_array()) {
          recipe.spec.a22[c] = r.numbers(comps[c], path);
          check_vertical_scaling(recipe.spec.a22[c], "a22");
        } else {
          recipe.spec.a22[c] = vertical_scaling(stops.size() - 1, r.number(comps[c], path), signs, seed, c);
        }
      } catch (const InputError& e) {
        if (std::string(e.what()).rfind(source, 0) == 0) throw;
        r.fail(path, e.what());
      }
    }
  }
  try {
    make_palette(recipe.spec, 2);  // every other check (positions, counts) with its own words
  } catch (const InputError& e) {
    r.fail("", e.what());
  }
  return recipe;
}

PaletteRecipe read_palette_recipe(const std::string& path) { return parse_palette_recipe(read_text_file(path), path); }

}  // namespace ifsforge
