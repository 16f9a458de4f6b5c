// Polar IFS (seed 3.3.3, Eq. 30-32): PolarMap, polar systems and their breeding.
#include <pybind11/operators.h>

#include "bindings.h"
#include "ifsforge/design/breed.h"
#include "ifsforge/model/polar_map.h"

namespace ifsforge::python {

void bind_polar(py::module_& m) {
  py::class_<PolarMap>(m, "PolarMap",
                       "A map locally contractive about its centre P (Eq. 30-32): rho' = rho (tanh(k F) + 1) / 2, "
                       "theta' = G, with F = f0 + f1 tanh(rho) + f2 cos t + f3 sin t + f4 cos 2t + f5 sin 2t and "
                       "G = w t + g0 + g1 rho + g2 cos t + g3 sin t in polar coordinates (rho, t) about P.")
      .def(py::init([](std::array<double, 2> center, double k, std::array<double, PolarMap::kF> F,
                       std::array<double, PolarMap::kG> G, int winding) {
             PolarMap p;
             p.center = center;
             p.k = k;
             p.f = F;
             p.g = G;
             p.winding = winding;
             p.validate("PolarMap");
             return p;
           }),
           py::arg("center"), py::arg("k"), py::arg("F"), py::arg("G"), py::arg("winding") = PolarMap{}.winding)
      .def_readonly("center", &PolarMap::center)
      .def_readonly("k", &PolarMap::k)
      .def_readonly("F", &PolarMap::f)
      .def_readonly("G", &PolarMap::g)
      .def_readonly("winding", &PolarMap::winding)
      .def("f_bound", &PolarMap::f_bound, "sup F over the plane")
      .def("contraction", &PolarMap::contraction, "s_i of Eq. 30: |P w(M)| <= s_i |P M| for every M")
      .def("__call__", [](const PolarMap& p, std::array<double, 2> point) {
             std::array<double, 2> out;
             p.apply(point.data(), out.data());
             return out;
           }, py::arg("point"), "The image of (x, y)")
      .def(py::self == py::self)
      .def("__repr__", [](const PolarMap& p) {
        return "PolarMap(center=(" + std::to_string(p.center[0]) + ", " + std::to_string(p.center[1]) +
               "), k=" + std::to_string(p.k) + ", s=" + std::to_string(p.contraction()) + ")";
      });

  m.def("polar_ifs", [](const std::vector<PolarMap>& maps, std::optional<std::vector<double>> probabilities,
                        const std::string& name) { return polar_ifs(name, maps, probabilities.value_or(std::vector<double>{})); },
        py::arg("maps"), py::arg("probabilities") = py::none(), py::arg("name") = "polar",
        "A 2D system of polar maps; probabilities=None gives them in proportion to s_i^2.");

  py::reinterpret_borrow<py::class_<Ifs>>(m.attr("Ifs"))
      .def_property("polar_maps", &Ifs::polar_maps, &Ifs::set_polar_maps,
                    "one PolarMap or None (affine) per map; [] for an affine system. Setting it replaces each "
                    "polar map's affine map by its shadow x -> P + s (x - P), keeping its channel rows")
      .def_property_readonly("polar", &Ifs::polar, "whether the system has polar maps (3.3.3)");

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
