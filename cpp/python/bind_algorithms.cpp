// The rendering-algorithm catalogue's extras: recurrent and super IFS, condensation sets,
// algorithm parameters, self-congruent growth frames, string rewriting, Eq. 53 and Eq. 101.
#include "bindings.h"
#include "ifsforge/core/error.h"
#include "ifsforge/render/colour_bounds.h"
#include "ifsforge/render/frame.h"
#include "ifsforge/render/minimal_plotting.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/render/self_congruent.h"
#include "ifsforge/render/string_rewriting.h"

namespace ifsforge::python {
namespace {

py::array_t<double> matrix_array(const std::vector<double>& values, std::size_t n) {
  py::array_t<double> out({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(n)});
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

TransitionMatrix transitions_from(py::array_t<double, py::array::c_style | py::array::forcecast> matrix) {
  if (matrix.ndim() != 2 || matrix.shape(0) != matrix.shape(1))
    throw InputError("the transition matrix must be square (N x N)");
  const auto n = static_cast<std::size_t>(matrix.shape(0));
  return TransitionMatrix(n, std::vector<double>(matrix.data(), matrix.data() + n * n));
}

std::optional<Window> window_of(const std::optional<std::array<double, 4>>& w) {
  if (!w) return std::nullopt;
  return Window{(*w)[0], (*w)[1], (*w)[2], (*w)[3]};
}

void bind_algorithms(py::module_& m) {
  py::class_<Condensation>(m, "Condensation",
                           "A condensation set C (seed 3.1, Definitions 8-9): shapes in the xy plane added to every "
                           "iterate, W(B) = C u w_1(B) u ... (Eq. 15).")
      .def(py::init([](std::vector<Condensation::Path> polylines, std::vector<Condensation::Path> polygons,
                       std::vector<double> channels, double probability) {
             Condensation c;
             c.polylines = std::move(polylines);
             c.polygons = std::move(polygons);
             c.channels = std::move(channels);
             c.probability = probability;
             return c;
           }),
           py::arg("polylines") = std::vector<Condensation::Path>{}, py::arg("polygons") = std::vector<Condensation::Path>{},
           py::arg("channels") = std::vector<double>{}, py::arg("probability") = 0.1,
           "polylines and polygons: lists of [x, y] points; channels: values of the layout's extra channels on C; "
           "probability: p_0, the share of the measure on C")
      .def_readwrite("polylines", &Condensation::polylines)
      .def_readwrite("polygons", &Condensation::polygons)
      .def_readwrite("channels", &Condensation::channels)
      .def_readwrite("probability", &Condensation::probability)
      .def("bounds", &Condensation::bounds, "(xmin, ymin, xmax, ymax)");

  // Extensions of the Ifs class registered by the model binding.
  auto ifs = py::reinterpret_borrow<py::class_<Ifs>>(m.attr("Ifs"));
  ifs.def_property(
         "transitions",
         [](const Ifs& s) -> py::object {
           if (!s.recurrent()) return py::none();
           return matrix_array(s.transitions().values(), s.size());
         },
         [](Ifs& s, const py::object& matrix) {
           s.set_transitions(matrix.is_none() ? TransitionMatrix() : transitions_from(matrix.cast<py::array>()));
         },
         "Recurrent IFS (3.3.1): N x N matrix, (i, j) = probability that map j follows map i, or None. Setting it "
         "replaces the probabilities by the chain's stationary distribution.")
      .def_property_readonly("recurrent", &Ifs::recurrent)
      .def("stationary_distribution", [](const Ifs& s) {
        const auto v = effective_transitions(s).stationary();
        return py::array_t<double>(v.size(), v.data());
      }, "m with m P = m: how often each map is applied in the long run (the probabilities of an ordinary IFS)")
      .def("piece_points", [](const Ifs& s) {
        const auto points = piece_points(s);
        py::array_t<double> out({static_cast<py::ssize_t>(points.size()), static_cast<py::ssize_t>(s.dim())});
        for (std::size_t i = 0; i < points.size(); ++i)
          for (int c = 0; c < s.dim(); ++c) out.mutable_at(i, c) = points[i][c];
        return out;
      }, "one point of each piece A_j of the attractor, shape (N, dim)")
      .def_property(
          "condensation",
          [](const Ifs& s) -> py::object {
            if (s.condensation().empty()) return py::none();
            return py::cast(s.condensation());
          },
          [](Ifs& s, const py::object& c) { s.set_condensation(c.is_none() ? Condensation() : c.cast<Condensation>()); },
          "the condensation set (a Condensation) or None")
      .def_property_readonly("condensation_box", [](const Ifs& s) -> py::object {
        if (s.condensation().empty()) return py::none();
        return py::cast(condensation_attractor_box(s));
      }, "(xmin, ymin, xmax, ymax) holding the attractor with its condensation set (C and every w_s(C)), "
         "or None: what renderers frame when given no window")
      .def_property_readonly("super_ifs", [](const Ifs& s) -> py::object {
        const SuperIfs& p = s.super_ifs();
        if (p.empty()) return py::none();
        py::dict d;
        d["names"] = p.names;
        d["sizes"] = p.sizes;
        d["probabilities"] = p.probabilities;
        d["variability"] = p.variability;
        return d;
      }, "super IFS (3.3.5): {'names', 'sizes', 'probabilities', 'variability'} of the member systems, or None")
      .def("member", &super_member, py::arg("n"), "member system n of a super IFS as its own Ifs");

  m.def("make_super_ifs", [](const std::string& name, const std::vector<Ifs>& members,
                             std::optional<std::vector<double>> probabilities, int variability) {
    return make_super_ifs(name, members, probabilities.value_or(std::vector<double>{}), variability);
  }, py::arg("name"), py::arg("members"), py::arg("probabilities") = py::none(), py::arg("variability") = 2,
     "A super IFS (Eq. 38): the members' maps in one Ifs, member n chosen with probability P_n (default equal); "
     "render its V-variable fractals with algorithm 'dia-s'.");

  m.def("renderer_parameters", [](const std::string& name) {
    std::vector<std::tuple<std::string, std::string, std::string>> out;
    for (const auto& p : renderer(name).parameters()) out.emplace_back(p.name, p.default_value, p.description);
    return out;
  }, py::arg("algorithm"), "(name, default, description) of every setting the algorithm reads from `parameters`");

  m.def("rewrite_strings", &rewrite_strings, py::arg("ifs"), py::arg("length"),
        "The seed's string rewriting (5.6): every address string of `length` maps, 'w2w1w3' ...");

  m.def("proximity_bound", [](const Ifs& s, int width, std::optional<int> height, std::optional<std::array<double, 4>> window) {
    const Frame frame = Frame::fit(s, width, height.value_or(width), window_of(window));
    return proximity_bound(s, frame);
  }, py::arg("ifs"), py::arg("width"), py::arg("height") = py::none(), py::arg("window") = py::none(),
     "Eq. 53: delta / (1 - s), the largest distance from a pixel minimal plotting plots to the attractor");

  m.def("colour_bounds", [](const Ifs& s, int levels) {
    const Bounds b = colour_bounds(s, levels);
    return py::make_tuple(py::array_t<double>(b.lo.size(), b.lo.data()), py::array_t<double>(b.hi.size(), b.hi.data()));
  }, py::arg("ifs"), py::arg("levels") = 8,
     "Eq. 101's minR/maxR (and the other channels): bounds of the extra channels from `levels` levels of point "
     "recursion, (lo, hi)");

  m.def("growth_frames", [](const Ifs& s, int width, std::optional<int> height, std::optional<std::array<double, 4>> window,
                            int threads, std::optional<py::dict> parameters, const py::object& progress) {
    RenderOptions o;
    o.width = width;
    o.height = height.value_or(width);
    o.window = window_of(window);
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

const Binding registered(40, &bind_algorithms);

}  // namespace
}  // namespace ifsforge::python
