// Interactive design: preview point clouds (the collage of chapter 4), morphing, breeding polar systems.
#include "bindings.h"
#include "ifsforge/design/breed.h"
#include "ifsforge/design/morph.h"
#include "ifsforge/design/preview.h"

namespace ifsforge::python {
namespace {

/// A read-only numpy view of `data` kept alive by `owner` (no copy: previews are redrawn
/// while a value is dragged).
template <typename T>
py::array_t<T> view(const std::vector<T>& data, std::vector<py::ssize_t> shape, const py::object& owner) {
  py::array_t<T> out(shape, data.data(), owner);
  py::detail::array_proxy(out.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return out;
}

}  // namespace

void bind_design(py::module_& m) {
  add_choices<PreviewColoring>(m, "coloring");
  py::class_<PreviewCloud>(m, "PreviewCloud",
                           "Points of the attractor with colors, and the collage frames, for a viewport preview.")
      .def_readonly("count", &PreviewCloud::count)
      .def_property_readonly("positions", [](py::object self) {
        const auto& c = self.cast<const PreviewCloud&>();
        return view(c.positions, {static_cast<py::ssize_t>(c.count), 3}, self);
      }, "float32 (count, 3); z = 0 for planar systems")
      .def_property_readonly("colors", [](py::object self) {
        const auto& c = self.cast<const PreviewCloud&>();
        return view(c.colors, {static_cast<py::ssize_t>(c.count), 4}, self);
      }, "float32 (count, 4) RGBA in [0, 1]")
      .def_property_readonly("pieces", [](py::object self) {
        const auto& c = self.cast<const PreviewCloud&>();
        return view(c.pieces, {static_cast<py::ssize_t>(c.count)}, self);
      }, "uint32 (count,): the map applied last, i.e. the piece w_i(A) holding the point")
      .def_property_readonly("bounds", [](const PreviewCloud& c) {
        return py::make_tuple(py::array_t<double>(c.bounds.lo.size(), c.bounds.lo.data()),
                              py::array_t<double>(c.bounds.hi.size(), c.bounds.hi.data()));
      }, "(lo, hi) per channel")
      .def_property_readonly("frame_positions", [](py::object self) {
        const auto& c = self.cast<const PreviewCloud&>();
        return view(c.frame_positions, {static_cast<py::ssize_t>(c.frame_pieces.size()), 3}, self);
      }, "float32 (2 x segments, 3): the bounding box, then its image under each map")
      .def_property_readonly("frame_colors", [](py::object self) {
        const auto& c = self.cast<const PreviewCloud&>();
        return view(c.frame_colors, {static_cast<py::ssize_t>(c.frame_pieces.size()), 4}, self);
      })
      .def_property_readonly("frame_pieces", [](py::object self) {
        const auto& c = self.cast<const PreviewCloud&>();
        return view(c.frame_pieces, {static_cast<py::ssize_t>(c.frame_pieces.size())}, self);
      }, "per end point: the map index, or len(system) for the bounding box")
      .def_property_readonly("coloring", [](const PreviewCloud& c) { return std::string(name_of(c.coloring)); });

  options_class<PreviewOptions>(m, "PreviewOptions", "The settings of preview_cloud() (keywords of the same names).")
      .def_readwrite("count", &PreviewOptions::count, "points in the cloud")
      .def_readwrite("seed", &PreviewOptions::seed)
      .def_property("coloring", [](const PreviewOptions& o) { return std::string(name_of(o.coloring)); },
                    [](PreviewOptions& o, const std::string& c) { o.coloring = parse_name<PreviewColoring>(c); },
                    "auto, pieces (the collage of Eq. 41) or channels (the layout's color channels)")
      .def_readwrite("highlight", &PreviewOptions::highlight, "a map whose piece stays bright (-1: none)")
      .def_readwrite("threads", &PreviewOptions::threads, "0: every core; the cloud never depends on it");
  m.def("preview_cloud",
        [](const Ifs& ifs, const py::object& count, const py::kwargs& kwargs) {
          py::dict given(kwargs);
          add_option(given, "count", count);
          const PreviewOptions o = options_from<PreviewOptions>("preview_cloud", given);
          py::gil_scoped_release release;
          return preview_cloud(ifs, o);
        },
        py::arg("ifs"), py::arg("count") = py::none(),
        "A seeded cloud of points on the attractor colored by piece (the collage of Eq. 41) or by the "
        "layout's color channels, plus the collage frames: the PreviewOptions given as keywords. "
        "Identical for any thread count.");
  m.def("piece_color", [](std::size_t index, bool dim) {
    float rgba[4];
    piece_color(index, dim, rgba);
    return py::make_tuple(rgba[0], rgba[1], rgba[2], rgba[3]);
  }, py::arg("index"), py::arg("dim") = false, "The RGBA color previews give map `index`'s piece.");
  m.def("morph", &morph, py::arg("from_system"), py::arg("to_system"), py::arg("t"),
        "The system at t in [0, 1] between two systems of one layout (parameters of Eq. 5 interpolated; "
        "continuous in t, so frames animate smoothly).");
  m.def("pad_maps", &pad_maps, py::arg("ifs"), py::arg("maps"),
        "The system with its last map repeated up to `maps` maps (same attractor and measure).");

  options_class<BreedOptions>(m, "BreedOptions", "The settings of breed(); its keywords are these fields, their defaults these.")
      .def_readwrite("count", &BreedOptions::count, "phenotypes to draw")
      .def_readwrite("seed", &BreedOptions::seed, "the same seed draws the same phenotypes")
      .def_readwrite("maps", &BreedOptions::maps, "maps per phenotype (2..16); 0: 2 to 4, drawn")
      .def_readwrite("probe", &BreedOptions::probe, "side of the chaos render that judges a draw")
      .def_readwrite("min_coverage", &BreedOptions::min_coverage, "share of the probe the attractor must cover")
      .def_readwrite("max_coverage", &BreedOptions::max_coverage, "share of the probe it may cover at most")
      .def_readwrite("min_extent", &BreedOptions::min_extent, "attractor's box side relative to the centres' spread")
      .def_readwrite("attempts", &BreedOptions::attempts, "draws per phenotype before giving up");
  m.def("breed", [](const py::kwargs& kwargs) {
    const BreedOptions o = options_from<BreedOptions>("breed", kwargs);
    py::gil_scoped_release release;
    return breed(o);
  }, "The BreedOptions given as keywords. Random locally contractive polar systems (the seed's phenotypes), "
     "each redrawn from its own stream until its attractor is neither a point nor a blob: the same for a seed.");
}

}  // namespace ifsforge::python
