// Terrain and palette recipes (one target: they share the recipe reader).
#include "fuzz_common.h"
#include "ifsforge/io/terrain_recipe.h"
#include "ifsforge/io/palette_recipe.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::with_text(data, size, [](const std::string& text) { ifsforge::parse_terrain_recipe(text, "fuzz.json"); });
  fuzz::with_text(data, size, [](const std::string& text) { ifsforge::parse_palette_recipe(text, "fuzz.json"); });
  return 0;
}
