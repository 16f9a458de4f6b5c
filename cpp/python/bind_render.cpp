// The 2D renderers, tone mapping and box counting.
#include "bindings.h"
#include "ifsforge/core/error.h"
#include "ifsforge/render/box_counting.h"
#include "ifsforge/render/color_bounds.h"
#include "ifsforge/render/frame.h"
#include "ifsforge/render/minimal_plotting.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/render/self_congruent.h"
#include "ifsforge/render/string_rewriting.h"
#include "ifsforge/render/tone_map.h"

namespace ifsforge::python {

py::dict capability_dict(const Capabilities& c);  // bind_model.cpp

RenderOptions render_options(const py::dict& given) {
  RenderOptions o = options_from<RenderOptions>("render", given);
  if (!given.contains("height") || given["height"].is_none()) o.height = o.width;  // square by default
  return o;
}

void bind_render(py::module_& m) {
  py::class_<Raster>(m, "Raster", "Density (hits or measure) and mean channel values per pixel.")
      .def_readonly("width", &Raster::width)
      .def_readonly("height", &Raster::height)
      .def_readonly("points", &Raster::points, "points plotted or leaves visited")
      .def_readonly("channel_names", &Raster::channel_names)
      .def_property_readonly("density", [](const Raster& r) { return to_numpy(r.density, {r.height, r.width}); })
      .def_property_readonly("channels", [](const Raster& r) {
        return to_numpy(r.channels, {r.height, r.width, static_cast<py::ssize_t>(r.channel_count())});
      })
      .def_property_readonly("depth", [](const Raster& r) -> py::object {
        if (r.depth.empty()) return py::none();
        return to_numpy(r.depth, {r.height, r.width});
      }, "3D systems: per-pixel largest depth towards the viewer (-inf where empty), else None")
      .def_property_readonly("mask", [](const Raster& r) {
        py::array_t<bool> out({r.height, r.width});
        for (std::size_t i = 0; i < r.density.size(); ++i) out.mutable_data()[i] = r.density[i] > 0.0f;
        return out;
      }, "pixels the attractor covers")
      .def("covered", &Raster::covered)
      .def("to_image", [](const Raster& r, const py::object& mode, const py::object& gamma, const py::object& invert,
                          const py::kwargs& kwargs) {
        py::dict given(kwargs);
        add_option(given, "mode", mode);
        add_option(given, "gamma", gamma);
        add_option(given, "invert", invert);
        return image_to_numpy(tone_map(r, options_from<ToneOptions>("to_image", given)));
      }, py::arg("mode") = py::none(), py::arg("gamma") = py::none(), py::arg("invert") = py::none(),
         "The picture (float32 (h, w[, c])) with the ToneOptions given as keywords (mode, gamma, invert). mode: "
         "auto, binary, density, color (Eq. 101 normalization; HSI converted to RGB) or shaded (3D).");

  options_class<ToneOptions>(m, "ToneOptions", "How Raster.to_image turns a raster into a picture.")
      .def_readwrite("mode", &ToneOptions::mode, "auto, binary, density, color or shaded")
      .def_readwrite("gamma", &ToneOptions::gamma, "density: v^(1/gamma) after the log")
      .def_readwrite("invert", &ToneOptions::invert, "binary and density: dark attractor on white");

  options_class<RenderOptions>(m, "RenderOptions",
                               "The settings of render(); its keywords are these fields, their defaults these.")
      .def_readwrite("width", &RenderOptions::width)
      .def_readwrite("height", &RenderOptions::height, "render(): default the width")
      .def_property("window", [](const RenderOptions& o) { return window_tuple(o.window); },
                    [](RenderOptions& o, const std::optional<std::array<double, 4>>& w) { o.window = window_argument(w); },
                    "(xmin, ymin, xmax, ymax); None: the attractor's bounds")
      .def_property("view", [](const RenderOptions& o) { return std::array<double, 2>{o.view.yaw, o.view.pitch}; },
                    [](RenderOptions& o, const std::array<double, 2>& v) { o.view = View{v[0], v[1]}; },
                    "(yaw, pitch) in degrees, for 3D systems")
      .def_property("iterations", [](const RenderOptions& o) { return o.iterations; },
                    [](RenderOptions& o, long long v) { o.iterations = count_argument(v, "iterations"); },
                    "random iteration: points to plot (0: Eq. 44 or Eq. 45)")
      .def_readwrite("binary", &RenderOptions::binary, "only coverage matters (sets the default counts)")
      .def_readwrite("points_per_pixel", &RenderOptions::points_per_pixel, "PEPP of Eq. 44")
      .def_property("skip", [](const RenderOptions& o) { return o.skip; },
                    [](RenderOptions& o, long long v) { o.skip = count_argument(v, "skip"); },
                    "points not plotted at the start (5.1.1)")
      .def_readwrite("depth", &RenderOptions::depth, "recursive renderers: 0 picks Eq. 59 and a pixel-size cut")
      .def_readwrite("seed", &RenderOptions::seed)
      .def_readwrite("threads", &RenderOptions::threads, "0: every core; the image never depends on it")
      .def_property("progress", [](const RenderOptions&) { return py::none(); },
                    [](RenderOptions& o, const py::object& f) { o.progress = wrap_progress(f); },
                    "progress(fraction) returning False cancels (write-only)")
      .def_property("reference_image", [](const RenderOptions& o) -> py::object {
                      if (!o.reference_image) return py::none();
                      return image_to_numpy(*o.reference_image);
                    },
                    [](RenderOptions& o, const py::array& a) { o.reference_image = std::make_shared<Image>(image_from_numpy(a)); },
                    "color stealing (5.1.2): the picture colors are taken from")
      .def_property("reference_system", [](const RenderOptions& o) -> std::optional<Ifs> {
                      if (!o.reference_system) return std::nullopt;
                      return *o.reference_system;
                    },
                    [](RenderOptions& o, const Ifs& s) { o.reference_system = std::make_shared<Ifs>(s); },
                    "color stealing: the system that walks the reference image")
      .def_property("parameters", [](const RenderOptions& o) { return o.parameters; },
                    [](RenderOptions& o, const py::dict& parameters) {
                      // Algorithm settings: values may be given as numbers or text.
                      o.parameters.clear();
                      for (const auto& item : parameters)
                        o.parameters[py::str(item.first)] = py::isinstance<py::bool_>(item.second)
                                                                ? std::string(item.second.cast<bool>() ? "1" : "0")
                                                                : std::string(py::str(item.second));
                    },
                    "algorithm settings by name (renderer_parameters lists them)");

  m.def("render",
        [](const Ifs& ifs, const std::string& algorithm, const py::object& width, const py::object& height,
           const py::kwargs& kwargs) {
          py::dict given(kwargs);
          add_option(given, "width", width);
          add_option(given, "height", height);
          RenderOptions o = render_options(given);
          const Renderer& r = renderer(algorithm);
          check_parameters(r, o);
          py::gil_scoped_release release;
          return r.render(ifs, o);
        },
        py::arg("ifs"), py::arg("algorithm") = "chaos", py::arg("width") = py::none(), py::arg("height") = py::none(),
        "The RenderOptions given as keywords (width, height (default: width), window, view, iterations, depth, "
        "seed, threads, binary, points_per_pixel, skip, progress, reference_image, reference_system, "
        "parameters). "
        "Render a system with a chapter-5 algorithm. window = (xmin, ymin, xmax, ymax); view = (yaw, pitch) "
        "for 3D; iterations=0 and depth=0 pick Eq. 44/45 and Eq. 59; progress(fraction) returning False cancels; "
        "parameters: algorithm settings by name (renderer_parameters(algorithm) lists them).");

  m.def("renderers", [] {
    std::vector<std::pair<std::string, std::string>> out;
    for (const Renderer* r : renderers()) out.emplace_back(r->name(), r->description());
    return out;
  }, "(name, description) of every algorithm");
  m.def("renderer_capabilities", [] {
    py::dict out;
    for (const auto& [name, caps] : renderer_capabilities()) out[py::str(name)] = capability_dict(caps);
    return out;
  }, "{algorithm: {capability: bool}}: the systems each renderer draws (recurrent, polar, average_contractive, "
     "overlapping, condensation, 2d, 3d); render() refuses others, naming the algorithms that draw them");
  m.def("seed_reference", [](const std::string& name) {
    const SeedReference s = seed_reference(name);
    return py::make_tuple(s.section, s.operations > 0 ? py::object(py::float_(s.operations)) : py::object(py::none()));
  }, py::arg("algorithm"),
     "(section, operations): where the seed describes the algorithm and its operation estimate for a 1000 x 1000 "
     "image of a 5-map IFS (5.13.1, Eq. 75-88), or None where it gives none");
  m.def("default_iterations", &default_iterations, py::arg("width"), py::arg("height"), py::arg("binary") = RenderOptions{}.binary,
        py::arg("points_per_pixel") = RenderOptions{}.points_per_pixel, "Eq. 44 (density) or Eq. 45 (binary)");
  m.def("default_depth", &default_depth, py::arg("maps"), py::arg("width"), py::arg("height"), "Eq. 59");
  m.def("hsi_to_rgb", [](double h, double s, double i) {
    float rgb[3];
    hsi_to_rgb(h, s, i, rgb);
    return py::make_tuple(rgb[0], rgb[1], rgb[2]);
  });

  py::class_<BoxCounting>(m, "BoxCounting")
      .def_readonly("box_sizes", &BoxCounting::box_sizes)
      .def_readonly("box_counts", &BoxCounting::box_counts)
      .def_readonly("dimension", &BoxCounting::dimension);
  m.def("box_counting", [](const Raster& r, int min_box, int max_box) { return box_counting(r, min_box, max_box); },
        py::arg("raster"), py::arg("min_box") = 2, py::arg("max_box") = 0);
  m.def("box_counting", [](py::array_t<bool, py::array::c_style | py::array::forcecast> mask, int min_box, int max_box) {
        if (mask.ndim() != 2) throw InputError("the mask must be 2D");
        std::vector<std::uint8_t> v(mask.data(), mask.data() + mask.size());
        return box_counting(v, static_cast<int>(mask.shape(1)), static_cast<int>(mask.shape(0)), min_box, max_box);
      }, py::arg("mask"), py::arg("min_box") = 2, py::arg("max_box") = 0,
      "Box-counting dimension: least-squares slope over boxes of 2^k pixels.");

  m.def("renderer_parameters", [](const std::string& name) {
    std::vector<std::tuple<std::string, std::string, std::string>> out;
    for (const auto& p : renderer(name).parameters()) out.emplace_back(p.name, p.default_value, p.description);
    return out;
  }, py::arg("algorithm"), "(name, default, description) of every setting the algorithm reads from `parameters`");

  m.def("proximity_bound", [](const Ifs& s, int width, std::optional<int> height, std::optional<std::array<double, 4>> window) {
    const Frame frame = Frame::fit(s, width, height.value_or(width), window_argument(window));
    return proximity_bound(s, frame);
  }, py::arg("ifs"), py::arg("width"), py::arg("height") = py::none(), py::arg("window") = py::none(),
     "Eq. 53: delta / (1 - s), the largest distance from a pixel minimal plotting plots to the attractor");

  m.def("color_bounds", [](const Ifs& s, int levels) {
    const Bounds b = color_bounds(s, levels);
    return py::make_tuple(py::array_t<double>(b.lo.size(), b.lo.data()), py::array_t<double>(b.hi.size(), b.hi.data()));
  }, py::arg("ifs"), py::arg("levels") = 8,
     "Eq. 101's minR/maxR (and the other channels): bounds of the extra channels from `levels` levels of point "
     "recursion, (lo, hi)");

  m.def("growth_frames", [](const Ifs& s, int width, std::optional<int> height, std::optional<std::array<double, 4>> window,
                            int threads, std::optional<py::dict> parameters, const py::object& progress) {
    RenderOptions o;
    o.width = width;
    o.height = height.value_or(width);
    o.window = window_argument(window);
    o.threads = threads;
    o.progress = wrap_progress(progress);
    if (parameters)
      for (const auto& item : *parameters) o.parameters[py::str(item.first)] = std::string(py::str(item.second));
    py::gil_scoped_release release;
    return growth_frames(s, o);
  }, py::arg("ifs"), py::arg("width") = 512, py::arg("height") = py::none(), py::arg("window") = py::none(),
     py::arg("threads") = 0, py::arg("parameters") = py::none(), py::arg("progress") = py::none(),
     "Self-congruent growth (5.11): every frame, from the initiator to the grown structure (parameters as for "
     "render(..., 'self-congruent'), except frame)");
}

}  // namespace ifsforge::python
