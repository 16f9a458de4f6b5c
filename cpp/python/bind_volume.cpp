// Volumes: the four volumetric renderers of Table 2 and the sparse volume they make.
#include <algorithm>
#include <cstring>

#include "bindings.h"
#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/volume/volume_renderer.h"

namespace ifsforge::python {

py::dict capability_dict(const Capabilities& c);  // bind_model.cpp

namespace {

const char* color_model_name(ColorModel m) {
  switch (m) {
    case ColorModel::None: return "none";
    case ColorModel::Gray: return "gray";
    case ColorModel::Rgb: return "rgb";
    case ColorModel::Hsi: return "hsi";
    case ColorModel::Rgba: return "rgba";
  }
  return "none";
}

py::array_t<std::int32_t> coords_of(const Volume& v) {
  py::array_t<std::int32_t> out({static_cast<py::ssize_t>(v.size()), py::ssize_t(3)});
  std::int32_t* p = out.mutable_data();
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto c = VoxelGrid::coord(v.keys[i]);
    p[3 * i] = c[0];
    p[3 * i + 1] = c[1];
    p[3 * i + 2] = c[2];
  }
  return out;
}

py::array_t<float> attribute_array(const VolumeAttribute& a, std::size_t voxels) {
  if (a.components == 1) return to_numpy(a.values, {static_cast<py::ssize_t>(voxels)});
  return to_numpy(a.values, {static_cast<py::ssize_t>(voxels), py::ssize_t(a.components)});
}

}  // namespace

void bind_volume(py::module_& m) {
  add_choices<VolumeDensity>(m, "density");
  add_choices<ColorScale>(m, "color_scale");
  add_choices<EscapeNorm>(m, "escape_norm");
  py::class_<Volume>(m, "Volume",
                     "A sparse volume: the occupied voxels of a grid, sorted by (i, j, k), with a density and "
                     "the mean of every extra channel per voxel.")
      .def("__len__", &Volume::size)
      .def_property_readonly("coords", &coords_of, "(n, 3) int32 voxel indices (i, j, k)")
      .def_property_readonly("positions", [](const Volume& v) {
        py::array_t<double> out({static_cast<py::ssize_t>(v.size()), py::ssize_t(3)});
        double* p = out.mutable_data();
        for (std::size_t i = 0; i < v.size(); ++i) {
          const auto c = VoxelGrid::coord(v.keys[i]);
          const auto w = v.grid.center(c[0], c[1], c[2]);
          std::copy(w.begin(), w.end(), p + 3 * i);
        }
        return out;
      }, "(n, 3) world positions of the voxel centres")
      .def_property_readonly("density", [](const Volume& v) {
        return to_numpy(v.density, {static_cast<py::ssize_t>(v.size())});
      }, "(n,) float32: 1, hits or measure (see density_mode)")
      .def_property_readonly("channels", [](const Volume& v) {
        return to_numpy(v.channels, {static_cast<py::ssize_t>(v.size()), static_cast<py::ssize_t>(v.channel_count())});
      }, "(n, c) float32 mean channel values, in the system's units")
      .def_readonly("channel_names", &Volume::channel_names)
      .def_readonly("channel_lo", &Volume::channel_lo)
      .def_readonly("channel_hi", &Volume::channel_hi)
      .def_property_readonly("color_model", [](const Volume& v) { return color_model_name(v.color_model); })
      .def_property_readonly("density_mode", [](const Volume& v) { return std::string(name_of(v.density_mode)); })
      .def_property_readonly("origin", [](const Volume& v) { return v.grid.origin; },
                             "world position of voxel (0, 0, 0)'s low corner")
      .def_property_readonly("voxel_size", [](const Volume& v) { return v.grid.voxel_size; })
      .def_property_readonly("dims", [](const Volume& v) { return v.grid.dims; }, "voxels along x, y, z")
      .def_property_readonly("bounds", [](const Volume& v) { return v.grid.box(); },
                             "the grid's world box (xmin, ymin, zmin, xmax, ymax, zmax)")
      .def_readonly("algorithm", &Volume::algorithm)
      .def_readonly("depth", &Volume::depth, "recursion depth (prr), rewriting levels (dia), escape bound (eta)")
      .def_readonly("points", &Volume::points, "leaves, random points, mapped voxels or search steps")
      .def("attributes", [](const Volume& v, const std::optional<std::string>& scale) {
        py::dict out;
        const auto attributes = scale ? volume_attributes(v, parse_name<ColorScale>(*scale)) : volume_attributes(v);
        for (const auto& a : attributes)
          out[py::str(a.name)] = attribute_array(a, v.size());
        return out;
      }, py::arg("color_scale") = py::none(),
         "The output attributes in [0, 1] (color_scale: auto (None), range or clamp): 'color' (n, 3) RGB (HSI converted, gray repeated), 'gray', 'alpha', ...")
      .def_property_readonly("color", [](const Volume& v) -> py::object {
        for (const auto& a : volume_attributes(v))
          if (a.name == "color") return attribute_array(a, v.size());
        return py::none();
      }, "(n, 3) RGB in [0, 1], or None without color")
      .def("to_dense", [](const Volume& v, const std::string& what) {
        check_memory(v.grid.cells() * 4.0, "a dense " + std::to_string(v.grid.dims[0]) + "x" +
                                               std::to_string(v.grid.dims[1]) + "x" + std::to_string(v.grid.dims[2]) + " array");
        const std::vector<float>* values = &v.density;
        std::vector<float> ones;
        if (what == "occupancy") {
          ones.assign(v.size(), 1.0f);
          values = &ones;
        } else if (what != "density") {
          throw InputError("to_dense takes 'density' or 'occupancy', got '" + what + "'");
        }
        py::array_t<float> out({v.grid.dims[0], v.grid.dims[1], v.grid.dims[2]});
        float* p = out.mutable_data();
        std::fill(p, p + out.size(), 0.0f);
        for (std::size_t i = 0; i < v.size(); ++i) {
          const auto c = VoxelGrid::coord(v.keys[i]);
          p[(std::size_t(c[0]) * v.grid.dims[1] + c[1]) * v.grid.dims[2] + c[2]] = (*values)[i];
        }
        return out;
      }, py::arg("what") = "density", "A dense (nx, ny, nz) float32 array (small grids only).");

  options_class<VolumeOptions>(m, "VolumeOptions",
                               "The settings of render_volume(); its keywords are these fields, their defaults these.")
      .def_readwrite("resolution", &VolumeOptions::resolution, "voxels along the longest side of the grid's box")
      .def_readwrite("bounds", &VolumeOptions::bounds, "(xmin, ymin, zmin, xmax, ymax, zmax); None: the attractor's box")
      .def_property("density", [](const VolumeOptions& o) { return std::string(name_of(o.density)); },
                    [](VolumeOptions& o, const std::string& d) { o.density = parse_name<VolumeDensity>(d); },
                    "binary, hits or measure")
      .def_readwrite("depth", &VolumeOptions::depth, "prr recursion depth / dia levels (0: until occupancy stops changing)")
      .def_property("iterations", [](const VolumeOptions& o) { return o.iterations; },
                    [](VolumeOptions& o, long long v) { o.iterations = count_argument(v, "iterations"); },
                    "ria points (0: doubled until occupancy stops changing)")
      .def_readwrite("escape_bound", &VolumeOptions::escape_bound, "eta: steps a voxel must survive (0: from the resolution)")
      .def_property("escape_norm", [](const VolumeOptions& o) { return std::string(name_of(o.escape_norm)); },
                    [](VolumeOptions& o, const std::string& n) { o.escape_norm = parse_name<EscapeNorm>(n); },
                    "eta: euclidean or linear (Eq. 55)")
      .def_readwrite("escape_pick_max", &VolumeOptions::escape_pick_max, "eta: Eq. 56's largest delta")
      .def_readwrite("seed", &VolumeOptions::seed, "ria only")
      .def_readwrite("threads", &VolumeOptions::threads, "0: every core; the volume never depends on it")
      .def_property("progress", [](const VolumeOptions&) { return py::none(); },
                    [](VolumeOptions& o, const py::object& f) { o.progress = wrap_progress(f); },
                    "progress(fraction) returning False cancels (write-only)");

  m.def("render_volume",
        [](const Ifs& ifs, const std::string& algorithm, const py::object& resolution, const py::kwargs& kwargs) {
          py::dict given(kwargs);
          add_option(given, "resolution", resolution);
          const VolumeOptions o = options_from<VolumeOptions>("render_volume", given);
          const VolumeRenderer& r = volume_renderer(algorithm);
          py::gil_scoped_release release;
          return r.render(ifs, o);
        },
        py::arg("ifs"), py::arg("algorithm") = "prr", py::arg("resolution") = py::none(),
        "The VolumeOptions given as keywords. "
        "Render a 3D system (xyz, xyz+gray, xyz+rgb, xyz+hsi, ...) into a sparse volume with one of the four "
        "renderers of the seed's Table 2: prr, ria, dia, eta. resolution: voxels along the longest side of "
        "bounds (xmin, ymin, zmin, xmax, ymax, zmax; default the attractor's box). density: binary, hits or "
        "measure. depth: prr recursion depth / dia levels (0: until occupancy stops changing); iterations: ria "
        "points (0: doubled until occupancy stops changing); escape_bound, escape_norm (euclidean, linear), "
        "escape_pick_max: eta (Eq. 55-56). progress(fraction) returning False cancels.");

  m.def("volume_renderers", [] {
    std::vector<std::pair<std::string, std::string>> out;
    for (const VolumeRenderer* r : volume_renderers()) out.emplace_back(r->name(), r->description());
    return out;
  }, "(name, description) of every volumetric renderer");
  m.def("volume_renderer_capabilities", [] {
    py::dict out;
    for (const auto& [name, caps] : volume_renderer_capabilities()) out[py::str(name)] = capability_dict(caps);
    return out;
  }, "{algorithm: {capability: bool}}: the systems each volumetric renderer draws; render_volume() refuses "
     "others, naming the volume algorithms that draw them");
}

}  // namespace ifsforge::python
