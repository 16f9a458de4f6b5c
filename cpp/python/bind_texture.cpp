// Fractal palettes (6.1.3.3): specs, recipes, lookup tables, application to images.
#include <cstring>

#include "bindings.h"
#include "ifsforge/core/error.h"
#include "ifsforge/io/pov_palette.h"
#include "ifsforge/texture/palette.h"
#include "ifsforge/io/palette_recipe.h"

namespace ifsforge::python {
namespace {

py::array_t<float> colors_to_numpy(const Palette& p) {
  py::array_t<float> out({static_cast<py::ssize_t>(p.size()), py::ssize_t(3)});
  std::memcpy(out.mutable_data(), p.colors.data(), p.size() * sizeof(p.colors[0]));
  return out;
}

Palette palette_from_numpy(const py::array& array) {
  auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!a || a.ndim() != 2 || a.shape(1) != 3 || a.shape(0) < 1)
    throw InputError("palette colors must be an array of shape (n, 3), RGB in [0, 1]");
  Palette p;
  p.colors.resize(a.shape(0));
  std::memcpy(p.colors.data(), a.data(), p.size() * sizeof(p.colors[0]));
  return p;
}

}  // namespace

void bind_texture(py::module_& m) {
  add_choices<ColorSpace>(m, "space");
  py::class_<PaletteSpec>(m, "PaletteSpec",
                          "Color stops, their positions and the roughness (a22 per map) of each component.")
      .def(py::init([](const std::string& space, std::vector<std::array<double, 3>> stops, std::vector<double> positions,
                       std::optional<std::array<std::vector<double>, 3>> a22) {
             PaletteSpec s;
             s.space = parse_name<ColorSpace>(space);
             s.stops = std::move(stops);
             s.positions = std::move(positions);
             if (a22) s.a22 = *a22;
             return s;
           }),
           py::arg("space") = "rgb", py::arg("stops") = std::vector<std::array<double, 3>>{},
           py::arg("positions") = std::vector<double>{}, py::arg("a22") = py::none(),
           "space: rgb, hls (hue degrees, lightness, saturation) or hsi (hue degrees, saturation, intensity); "
           "a22: three lists (one per component) of one factor per map, or of one factor for all.")
      .def_property("space", [](const PaletteSpec& s) { return std::string(name_of(s.space)); },
                    [](PaletteSpec& s, const std::string& v) { s.space = parse_name<ColorSpace>(v); })
      .def_readwrite("stops", &PaletteSpec::stops)
      .def_readwrite("positions", &PaletteSpec::positions)
      .def_readwrite("a22", &PaletteSpec::a22)
      .def("__repr__", [](const PaletteSpec& s) {
        return "PaletteSpec(space='" + std::string(name_of(s.space)) + "', " + std::to_string(s.stops.size()) +
               " stops)";
      });

  py::class_<Palette>(m, "Palette", "A color lookup table: RGB in [0, 1], entry 0 for the lowest input.")
      .def(py::init(&palette_from_numpy), py::arg("colors"), "From an (n, 3) array of RGB in [0, 1].")
      .def_property_readonly("colors", &colors_to_numpy, "(n, 3) float32 RGB")
      .def("__len__", &Palette::size)
      .def("lookup", &Palette::lookup, py::arg("t"), "The color at t in [0, 1], linear between entries.")
      .def("to_image", [](const Palette& p, int rows) { return image_to_numpy(palette_image(p, rows)); },
           py::arg("rows") = 1, "(rows, n, 3) float32: a strip (rows=1) or an n x rows texture")
      .def("color_map", &pov_color_map, py::arg("entries") = 256, py::arg("linear") = false,
           "A POV-Ray color_map (at most 256 entries, colors as srgb, or as linear rgb).")
      .def("pov_include", &pov_palette_include, py::arg("name"), py::arg("about") = "", py::arg("entries") = 256,
           "A POV-Ray include declaring IFS_Palette_<name> (linear rgb: parses without assumed_gamma).");

  py::class_<PaletteRecipe>(m, "PaletteRecipe", "A palette recipe file (ifsforge-palette/1).")
      .def(py::init<>(), "A recipe with the defaults (its entries are every front end's default size)")
      .def_readwrite("name", &PaletteRecipe::name)
      .def_readwrite("description", &PaletteRecipe::description)
      .def_readwrite("spec", &PaletteRecipe::spec)
      .def_readwrite("entries", &PaletteRecipe::entries)
      .def("make", [](const PaletteRecipe& r, std::optional<std::size_t> entries) {
        return make_palette(r.spec, entries.value_or(r.entries));
      }, py::arg("entries") = py::none(), "The palette (the recipe's entries unless given).");

  m.def("make_palette", [](const PaletteSpec& spec, std::size_t entries) {
    py::gil_scoped_release release;
    return make_palette(spec, entries);
  }, py::arg("spec"), py::arg("entries") = 256,
     "Fractal palette: each color component interpolated through the stops by Eq. 94; exact.");
  m.def("read_palette_recipe", &read_palette_recipe, py::arg("path"));
  m.def("parse_palette_recipe", &parse_palette_recipe, py::arg("text"), py::arg("source") = "palette recipe");
  m.def("apply_palette", [](const py::array& image, const Palette& palette, int threads) {
    Image in = image_from_numpy(image);
    Image out;
    {
      py::gil_scoped_release release;
      out = apply_palette(in, palette, threads);
    }
    return image_to_numpy(out);
  }, py::arg("image"), py::arg("palette"), py::arg("threads") = 0,
     "Color a gray (or RGB: by luminance) image through the palette; alpha is kept.");
  m.def("pov_color_map", &pov_color_map, py::arg("palette"), py::arg("entries") = 256, py::arg("linear") = false);
  m.def("hls_to_rgb", [](double h, double l, double s) {
    float rgb[3];
    hls_to_rgb(h, l, s, rgb);
    return py::make_tuple(rgb[0], rgb[1], rgb[2]);
  }, py::arg("hue"), py::arg("lightness"), py::arg("saturation"), "hue in degrees; lightness, saturation in [0, 1]");
}

}  // namespace ifsforge::python
