// Fractal interpolation (Eq. 90-94) and 2.5D IFS terrains (6.1.3.4): controls, recipes,
// sampling, height images, meshes and POV-Ray scenes.
#include <cmath>
#include <cstring>

#include "bindings.h"
#include "ifsforge/core/error.h"
#include "ifsforge/interpolation/fractal_interpolation.h"
#include "ifsforge/terrain/height_image.h"
#include "ifsforge/terrain/terrain.h"
#include "ifsforge/terrain/terrain_controls.h"
#include "ifsforge/io/terrain_mesh_file.h"
#include "ifsforge/io/terrain_povray.h"
#include "ifsforge/io/terrain_recipe.h"
#include "ifsforge/interpolation/vertical_scaling.h"

namespace ifsforge::python {
namespace {

template <typename T, std::size_t N>
py::array_t<T> rows_to_numpy(const std::vector<std::array<T, N>>& rows) {
  py::array_t<T> out({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(N)});
  if (!rows.empty()) std::memcpy(out.mutable_data(), rows.data(), rows.size() * sizeof(rows[0]));
  return out;
}

py::dict mesh_to_dict(const TriangleMesh& mesh) {
  py::dict d;
  d["positions"] = rows_to_numpy(mesh.positions);
  d["normals"] = rows_to_numpy(mesh.normals);
  d["uvs"] = rows_to_numpy(mesh.uvs);
  if (!mesh.colors.empty()) d["colors"] = rows_to_numpy(mesh.colors);
  d["triangles"] = rows_to_numpy(mesh.triangles);
  return d;
}

}  // namespace

void bind_terrain(py::module_& m) {
  add_choices<TerrainGrid>(m, "grid");
  add_choices<SignPattern>(m, "signs");
  add_choices<TerrainPovShape>(m, "pov_shape");
  add_choices<TerrainPovCamera>(m, "pov_camera");
  py::class_<FractalInterpolation>(m, "FractalInterpolation",
                                   "The continuous function through (x_i, F_i) whose graph is the attractor of the "
                                   "maps of Eq. 94; a22 are the vertical scaling factors (|a22| < 1).")
      .def(py::init<std::vector<double>, std::vector<double>, std::vector<double>>(), py::arg("x"), py::arg("values"),
           py::arg("a22"))
      .def("maps", &FractalInterpolation::maps)
      .def_property_readonly("x", &FractalInterpolation::x)
      .def_property_readonly("values", &FractalInterpolation::values)
      .def_property_readonly("vertical_scaling", &FractalInterpolation::vertical_scaling)
      .def_property_readonly("equally_spaced", &FractalInterpolation::equally_spaced)
      .def("map", &FractalInterpolation::map, py::arg("i"), "Map i (0-based) of Eq. 94")
      .def("to_ifs", &FractalInterpolation::to_ifs, py::arg("name") = "fractal interpolation",
           "The interpolation IFS on layout 'xy' (render it, write it as JSON)")
      .def("evaluate", py::overload_cast<double>(&FractalInterpolation::evaluate, py::const_), py::arg("x"))
      .def("evaluate", [](const FractalInterpolation& f, const std::vector<double>& xs) {
        std::vector<double> out;
        {
          py::gil_scoped_release release;
          out = f.evaluate(xs);
        }
        return py::array_t<double>(out.size(), out.data());
      }, py::arg("x"), "f at each x (deterministic; exact to 1e-14 of the data range)")
      .def("sample", [](const FractalInterpolation& f, std::size_t count) {
        std::vector<double> out;
        {
          py::gil_scoped_release release;
          out = f.sample(count);
        }
        return py::array_t<double>(out.size(), out.data());
      }, py::arg("count"), "f at count equally spaced points from x_0 to x_N (exact grid recursion)")
      .def("dimension", &FractalInterpolation::dimension, "box-counting dimension of the graph (Barnsley)");

  m.def("vertical_scaling", [](std::size_t maps, double roughness, const std::string& signs, std::uint64_t seed,
                               std::uint64_t stream) {
    return vertical_scaling(maps, roughness, parse_name<SignPattern>(signs), seed, stream);
  }, py::arg("maps"), py::arg("roughness"), py::arg("signs") = "random", py::arg("seed") = 0, py::arg("stream") = 0,
     "a22 factors of magnitude |roughness| with signs 'constant', 'alternating' or 'random' (seeded)");

  py::class_<TerrainControls>(m, "TerrainControls", "Step 1 of 6.1.3.4: control heights, displacements, roughness.")
      .def(py::init<>())
      .def_property("grid", [](const TerrainControls& c) { return std::string(name_of(c.grid)); },
                    [](TerrainControls& c, const std::string& g) { c.grid = parse_name<TerrainGrid>(g); })
      .def_readwrite("heights", &TerrainControls::heights, "rows x columns control heights")
      .def_readwrite("shift_u", &TerrainControls::shift_u, "displacement along the leading vectors (control spacings)")
      .def_readwrite("shift_v", &TerrainControls::shift_v, "displacement across them (control spacings)")
      .def_readwrite("radii", &TerrainControls::radii, "circular: radius of each leading circle, from 0")
      .def_readwrite("a22_u", &TerrainControls::a22_u, "roughness along the leading vectors (per map, or one)")
      .def_readwrite("a22_v", &TerrainControls::a22_v, "roughness across them (per map, or one)")
      .def_readwrite("a22_shift", &TerrainControls::a22_shift, "roughness of the displacement along them")
      .def_readwrite("size_x", &TerrainControls::size_x)
      .def_readwrite("size_y", &TerrainControls::size_y)
      .def("__repr__", [](const TerrainControls& c) {
        return "TerrainControls(grid='" + std::string(name_of(c.grid)) + "', " + std::to_string(c.heights.size()) +
               " x " + std::to_string(c.heights.empty() ? 0 : c.heights[0].size()) + ")";
      });

  py::class_<Terrain>(m, "Terrain", "Heights on a rows x columns lattice (leading vectors along the columns).")
      .def_property_readonly("grid", [](const Terrain& t) { return std::string(name_of(t.grid)); })
      .def_readonly("columns", &Terrain::columns)
      .def_readonly("rows", &Terrain::rows)
      .def_readonly("min_height", &Terrain::min_height)
      .def_readonly("max_height", &Terrain::max_height)
      .def_property_readonly("heights", [](const Terrain& t) { return to_numpy(t.heights, {t.rows, t.columns}); },
                             "(rows, columns) float32; row 0 is the south edge (circular: the centre)")
      .def_property_readonly("u", [](const Terrain& t) -> py::object {
        if (t.u.empty()) return py::none();
        return to_numpy(t.u, {t.rows, t.columns});
      }, "irregular/circular: displaced lattice parameter along the leading vectors")
      .def_property_readonly("v", [](const Terrain& t) -> py::object {
        if (t.v.empty()) return py::none();
        return to_numpy(t.v, {t.rows, t.columns});
      }, "irregular/circular: displaced lattice parameter across them")
      .def_property_readonly("extent", &Terrain::extent, "(xmin, ymin, xmax, ymax)")
      .def("positions", [](const Terrain& t) {
        py::array_t<double> out({py::ssize_t(t.rows), py::ssize_t(t.columns), py::ssize_t(3)});
        double* p = out.mutable_data();
        for (int r = 0; r < t.rows; ++r)
          for (int c = 0; c < t.columns; ++c) {
            const auto q = t.position(r, c);
            std::memcpy(p + (std::size_t(r) * t.columns + c) * 3, q.data(), sizeof q);
          }
        return out;
      }, "(rows, columns, 3) world positions (x east, y north, height)")
      .def("height_image", [](const Terrain& t, int width, int height, int threads) {
        Image image;
        {
          py::gil_scoped_release release;
          image = height_image(t, width, height, threads);
        }
        return image_to_numpy(image);
      }, py::arg("width") = 0, py::arg("height") = 0, py::arg("threads") = 0,
         "(height, width) float32 in [0, 1] (min_height..max_height), north up; write with write_png(..., 16)")
      .def("mesh", [](const Terrain& t, const py::object& up, int threads, const py::kwargs& kwargs) {
        const TerrainMeshOptions o = options_from<TerrainMeshOptions>("mesh", kwargs);
        const Up axes = up_argument(up).value_or(Up::z);
    TriangleMesh mesh;
        {
          py::gil_scoped_release release;
          mesh = terrain_mesh(t, o, threads);
          orient(mesh, axes);
        }
        return mesh_to_dict(mesh);
      }, py::kw_only(), py::arg("up") = "z", py::arg("threads") = 0,
         "The TerrainMeshOptions solid, base and palette given as keywords: dict of numpy arrays (positions, normals, uvs, display colors with a palette, triangles) in `up` axes: "
         "'z' (default) is ifsforge's (x, y, height), what write_mesh expects; 'y' gives (x, height, -y)");

  m.def("make_terrain", [](const TerrainControls& c, int columns, int rows, int threads, const py::object& progress) {
    ProgressCallback callback = wrap_progress(progress);
    py::gil_scoped_release release;
    return make_terrain(c, columns, rows, threads, callback);
  }, py::arg("controls"), py::arg("columns"), py::arg("rows"), py::arg("threads") = 0, py::arg("progress") = py::none(),
     "Interpolate the controls: leading vectors first, then every vertical (radial) vector. Exact at every "
     "sample; the same result for any thread count.");
  options_class<TerrainControlsOptions>(m, "TerrainControlsOptions",
                                        "What make_terrain_controls builds: the settings of a terrain without a "
                                        "recipe file (keywords of the same names).")
      .def_property("grid", [](const TerrainControlsOptions& o) { return std::string(name_of(o.grid)); },
                    [](TerrainControlsOptions& o, const std::string& g) { o.grid = parse_name<TerrainGrid>(g); },
                    "regular, irregular or circular")
      .def_readwrite("rows", &TerrainControlsOptions::rows, "control rows (circular: circles); 0: terrain_defaults")
      .def_readwrite("columns", &TerrainControlsOptions::columns, "control columns (circular: per circle); 0: terrain_defaults")
      .def_readwrite("base", &TerrainControlsOptions::base, "random heights: base + amplitude (2 u - 1)")
      .def_readwrite("amplitude", &TerrainControlsOptions::amplitude)
      .def_property("height_map", [](const TerrainControlsOptions& o) -> py::object {
                      if (!o.height_map) return py::none();
                      return image_to_numpy(*o.height_map);
                    },
                    [](TerrainControlsOptions& o, const py::array& map) { o.height_map = image_from_numpy(map); },
                    "sample the heights from this map (numpy image) instead of drawing them")
      .def_readwrite("window", &TerrainControlsOptions::window, "height_map: the part covered, [0, 1] image coordinates")
      .def_readwrite("low", &TerrainControlsOptions::low, "height_map: the height of value 0")
      .def_readwrite("high", &TerrainControlsOptions::high, "height_map: the height of value 1")
      .def_readwrite("radii", &TerrainControlsOptions::radii, "circular: radii (empty: evenly to size_x / 2)")
      .def_readwrite("shift", &TerrainControlsOptions::shift, "random displacement amplitude (0: none)")
      .def_readwrite("roughness", &TerrainControlsOptions::roughness, "(along, across) |a22|; (0, 0): bilinear")
      .def_property("signs", [](const TerrainControlsOptions& o) { return std::string(name_of(o.signs)); },
                    [](TerrainControlsOptions& o, const std::string& s) { o.signs = parse_name<SignPattern>(s); },
                    "random, alternating or constant")
      .def_readwrite("size_x", &TerrainControlsOptions::size_x)
      .def_readwrite("size_y", &TerrainControlsOptions::size_y);
  py::dict defaults;
  defaults["controls"] = kDefaultControls;
  defaults["circles"] = kDefaultCircles;
  defaults["circle_points"] = kDefaultCirclePoints;
  defaults["roughness"] = kDefaultRoughness;
  defaults["samples"] = kDefaultTerrainSamples;
  m.attr("terrain_defaults") = defaults;
  m.def("make_terrain_controls", [](std::uint64_t seed, const py::kwargs& kwargs) {
    return make_terrain_controls(options_from<TerrainControlsOptions>("make_terrain_controls", kwargs), seed);
  }, py::arg("seed"),
     "The TerrainControls the TerrainControlsOptions (keywords) describe, every random draw from `seed`: the "
     "one builder behind `ifsforge terrain` and the Blender add-on (one seed, one terrain).");
  m.def("set_roughness", [](TerrainControls& c, double along, double across, const std::string& signs,
                            std::uint64_t seed) { set_roughness(c, along, across, parse_name<SignPattern>(signs), seed); },
        py::arg("controls"), py::arg("along"), py::arg("across"), py::arg("signs"), py::arg("seed"),
        "a22 of |along| and |across| with the sign pattern (random signs from the seed's streams 1 and 2)");
  m.def("random_heights", [](const std::string& grid, int rows, int columns, std::vector<double> base,
                             double amplitude, std::uint64_t seed) {
    return random_heights(parse_name<TerrainGrid>(grid), rows, columns, base, amplitude, seed);
  }, py::arg("grid"), py::arg("rows"), py::arg("columns"), py::arg("base") = std::vector<double>{0.5},
     py::arg("amplitude") = 0.5, py::arg("seed") = 0, "base[r] + amplitude * uniform(-1, 1), seeded");
  m.def("random_shifts", &random_shifts, py::arg("controls"), py::arg("amplitude"), py::arg("seed") = 0,
        "Random displacements (|amplitude| < 0.5), zero where the outline must stay");
  m.def("sample_heights", [](TerrainControls& c, int rows, int columns, const py::array& map,
                             std::array<double, 4> window, double low, double high) {
    sample_heights(c, rows, columns, image_from_numpy(map), window, low, high);
  }, py::arg("controls"), py::arg("rows"), py::arg("columns"), py::arg("map"),
     py::arg("window") = std::array<double, 4>{0, 0, 1, 1}, py::arg("low") = 0.0, py::arg("high") = 1.0,
     "Control heights sampled from a height map (terrain inserts); window in [0, 1] image coordinates");

  py::class_<TerrainRecipe>(m, "TerrainRecipe", "A terrain recipe file (ifsforge-terrain/1).")
      .def_readwrite("name", &TerrainRecipe::name)
      .def_readwrite("description", &TerrainRecipe::description)
      .def_readwrite("controls", &TerrainRecipe::controls)
      .def_readwrite("columns", &TerrainRecipe::columns)
      .def_readwrite("rows", &TerrainRecipe::rows)
      .def_readwrite("palette", &TerrainRecipe::palette);
  m.def("read_terrain_recipe", &read_terrain_recipe, py::arg("path"));
  m.def("parse_terrain_recipe", &parse_terrain_recipe, py::arg("text"), py::arg("source") = "terrain recipe",
        py::arg("folder") = ".");

  options_class<TerrainMeshOptions>(m, "TerrainMeshOptions",
                                     "The settings of Terrain.mesh() and write_terrain_mesh() (keywords of the same "
                                     "names).")
      .def_readwrite("solid", &TerrainMeshOptions::solid,
                     "walls down to base and a floor: a watertight solid; else an open sheet")
      .def_property("base", [](const TerrainMeshOptions& o) -> std::optional<double> {
                      if (std::isnan(o.base)) return std::nullopt;
                      return o.base;
                    },
                    [](TerrainMeshOptions& o, double base) { o.base = base; },
                    "the floor height of a solid; None: 10% of the height range below the lowest point")
      .def_property("up", [](const TerrainMeshOptions& o) { return o.up; },
                    [](TerrainMeshOptions& o, const py::object& up) { o.up = up_argument(up); },
                    "write_terrain_mesh: the file's up axis ('y', 'z'; None: the format's, glTF/OBJ y, PLY z)")
      .def_readwrite("palette", &TerrainMeshOptions::palette, "vertex colors by height (empty: none)");
  m.def("write_terrain_mesh", [](const std::string& path, const Terrain& t, const py::object& palette, int threads,
                                 const py::kwargs& kwargs) {
    py::dict given(kwargs);
    add_option(given, "palette", palette);
    const TerrainMeshOptions o = options_from<TerrainMeshOptions>("write_terrain_mesh", given);
    py::gil_scoped_release release;
    write_terrain_mesh(path, t, o, threads);
  }, py::arg("path"), py::arg("terrain"), py::arg("palette") = py::none(), py::kw_only(), py::arg("threads") = 0,
     ".glb (palette strip embedded as base-color texture), .obj or .ply; uv = (normalized height, 0.5): the "
     "TerrainMeshOptions given as keywords");
  options_class<TerrainPovOptions>(m, "TerrainPovOptions",
                                    "The settings of write_terrain_pov() (keywords of the same names).")
      .def_property("shape", [](const TerrainPovOptions& o) { return std::string(name_of(o.shape)); },
                    [](TerrainPovOptions& o, const std::string& n) { o.shape = parse_name<TerrainPovShape>(n); },
                    "height_field (a 16-bit PNG beside the scene) or mesh2 (the triangles inlined)")
      .def_property("camera", [](const TerrainPovOptions& o) { return std::string(name_of(o.camera)); },
                    [](TerrainPovOptions& o, const std::string& n) { o.camera = parse_name<TerrainPovCamera>(n); },
                    "perspective (south-west, 35 degrees up) or top (orthographic, north up, the outline)")
      .def_readwrite("flat", &TerrainPovOptions::flat, "no lights: every point shows its palette color")
      .def_readwrite("aspect", &TerrainPovOptions::aspect, "the render's width / height (perspective camera)")
      .def_readwrite("title", &TerrainPovOptions::title, "first comment line and IFS_Title")
      .def_readwrite("palette_name", &TerrainPovOptions::palette_name, "the colors are IFS_Palette_<name>");
  m.def("write_terrain_pov", [](const std::string& path, const Terrain& t, std::optional<Palette> palette,
                                int threads, const py::kwargs& kwargs) {
    const TerrainPovOptions o = options_from<TerrainPovOptions>("write_terrain_pov", kwargs);
    const Palette p = palette.value_or(Palette{});
    py::gil_scoped_release release;
    return write_terrain_pov(path, t, p, o, threads);
  }, py::arg("path"), py::arg("terrain"), py::arg("palette") = py::none(), py::kw_only(), py::arg("threads") = 0,
     "POV-Ray scene (height_field + its 16-bit PNG, or mesh2) colored by the palette: the TerrainPovOptions "
     "given as keywords; returns the files written");
}

}  // namespace ifsforge::python
