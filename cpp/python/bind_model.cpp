// The model: affine maps, their parameters, channel layouts, systems and their analysis;
// condensation sets, recurrent and super IFS, polar maps.
#include <pybind11/operators.h>

#include "bindings.h"
#include "ifsforge/core/error.h"
#include "ifsforge/model/condensation.h"
#include "ifsforge/model/map_params.h"
#include "ifsforge/model/polar_map.h"
#include "ifsforge/model/capabilities.h"
#include "ifsforge/model/recurrent.h"
#include "ifsforge/model/super_ifs.h"

namespace ifsforge::python {
namespace {

AffineMap map_from_numpy(py::array_t<double, py::array::c_style | py::array::forcecast> matrix,
                         py::array_t<double, py::array::c_style | py::array::forcecast> offset) {
  if (matrix.ndim() != 2 || matrix.shape(0) != matrix.shape(1))
    throw InputError("the matrix must be square (n x n)");
  const int n = static_cast<int>(matrix.shape(0));
  if (offset.ndim() != 1 || offset.shape(0) != n)
    throw InputError("the offset must have " + std::to_string(n) + " numbers");
  return AffineMap(n, std::vector<double>(matrix.data(), matrix.data() + n * n),
                   std::vector<double>(offset.data(), offset.data() + n));
}

py::array_t<double> matrix_of(const AffineMap& map) {
  py::array_t<double> out({map.dim(), map.dim()});
  auto v = map.matrix();
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

py::array_t<double> points_of(const std::vector<Point>& points, int dim) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), static_cast<py::ssize_t>(dim)});
  auto r = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int c = 0; c < dim; ++c) r(i, c) = points[i][c];
  return out;
}

py::array_t<double> apply_points(const AffineMap& map, py::array_t<double, py::array::c_style | py::array::forcecast> points) {
  const int n = map.dim();
  const bool single = points.ndim() == 1;
  if ((single && points.shape(0) != n) || (!single && (points.ndim() != 2 || points.shape(1) != n)))
    throw InputError("points must have " + std::to_string(n) + " coordinates (shape (n,) or (k, n))");
  py::array_t<double> out(std::vector<py::ssize_t>(points.shape(), points.shape() + points.ndim()));
  const py::ssize_t count = single ? 1 : points.shape(0);
  for (py::ssize_t i = 0; i < count; ++i) map.apply(points.data() + i * n, out.mutable_data() + i * n);
  return out;
}

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

/// Condensation sets (seed 3.1), recurrent IFS (3.3.3) and super IFS (3.3.5) on the Ifs class.
void bind_model_extensions(py::module_& m, py::class_<Ifs>& ifs) {
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
}

/// Polar maps (seed 3.3.3, Eq. 30-32) and the Ifs's polar_maps.
void bind_polar_maps(py::module_& m, py::class_<Ifs>& ifs) {
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

  ifs.def_property("polar_maps", &Ifs::polar_maps, &Ifs::set_polar_maps,
                    "one PolarMap or None (affine) per map; [] for an affine system. Setting it replaces each "
                    "polar map's affine map by its shadow x -> P + s (x - P), keeping its channel rows")
      .def_property_readonly("polar", &Ifs::polar, "whether the system has polar maps (3.3.3)");
}

}  // namespace

py::dict capability_dict(const Capabilities& c) {
  py::dict out;
  for (const auto& [name, value] : capability_flags(c)) out[py::str(name)] = value;
  return out;
}

void bind_model(py::module_& m) {
  add_choices<Classification>(m, "classification");
  py::class_<AffineMap>(m, "AffineMap", "An affine map x' = A x + b on R^n (n = 1..8).")
      .def(py::init(&map_from_numpy), py::arg("matrix"), py::arg("offset"))
      .def(py::init<int>(), py::arg("dim"), "The identity on R^dim.")
      .def_property_readonly("dim", &AffineMap::dim)
      .def_property_readonly("matrix", &matrix_of)
      .def_property_readonly("offset", [](const AffineMap& a) { return py::array_t<double>(a.dim(), a.offset().data()); })
      .def("__call__", &apply_points, py::arg("points"), "Apply to one point (n,) or many (k, n).")
      .def("compose", &AffineMap::compose, py::arg("inner"), "self o inner")
      .def("inverse", [](const AffineMap& a) {
        auto inv = a.inverse();
        if (!inv) throw InputError("the map is singular and has no inverse");
        return *inv;
      })
      .def("determinant", &AffineMap::determinant, py::arg("k") = 0)
      .def("contraction_factor", &AffineMap::contraction_factor, py::arg("k") = 0,
           "Spectral norm of the leading k x k block (Eq. 8-9 in 2D); k=0: all of it.")
      .def("fixed_point", [](const AffineMap& a) -> py::object {
        auto p = a.fixed_point();
        if (!p) return py::none();
        return py::array_t<double>(a.dim(), p->data());
      })
      .def("params", &params_from_map, py::arg("spatial_dims"),
           "Scale, rotation, shear, reflection, translation of the spatial block.")
      .def_static("from_params", &map_from_params, py::arg("params"))
      .def("__repr__", [](const AffineMap& a) {
        return "AffineMap(" + py::repr(matrix_of(a)).cast<std::string>() + ", " +
               py::repr(py::array_t<double>(a.dim(), a.offset().data())).cast<std::string>() + ")";
      });

  py::class_<MapParams>(m, "MapParams",
                        "2D: A = [[Mx cos tx, -My sin ty], [Mx sin tx, My cos ty]] [[1, h], [0, 1]] F "
                        "(Eq. 5); 3D: A = Rz Ry Rx diag(M) Shear F. Angles in degrees.")
      .def(py::init([](int dim, std::array<double, 3> scale, std::array<double, 3> rotation,
                       std::array<double, 3> shear, std::array<bool, 3> reflect,
                       std::array<double, 3> translation) {
             return MapParams{dim, scale, rotation, shear, reflect, translation};
           }),
           py::arg("dim") = 2, py::arg("scale") = std::array<double, 3>{1, 1, 1},
           py::arg("rotation") = std::array<double, 3>{0, 0, 0}, py::arg("shear") = std::array<double, 3>{0, 0, 0},
           py::arg("reflect") = std::array<bool, 3>{false, false, false},
           py::arg("translation") = std::array<double, 3>{0, 0, 0})
      .def_readwrite("dim", &MapParams::dim)
      .def_readwrite("scale", &MapParams::scale)
      .def_readwrite("rotation", &MapParams::rotation)
      .def_readwrite("shear", &MapParams::shear)
      .def_readwrite("reflect", &MapParams::reflect)
      .def_readwrite("translation", &MapParams::translation);

  py::class_<ChannelLayout>(m, "ChannelLayout", "What each dimension means, e.g. 'xyz+rgb'.")
      .def(py::init<const std::string&>(), py::arg("text"))
      .def_property_readonly("text", &ChannelLayout::text)
      .def_property_readonly("dim", &ChannelLayout::dim)
      .def_property_readonly("spatial_dims", &ChannelLayout::spatial_dims)
      .def_property_readonly("names", &ChannelLayout::names)
      .def("index", &ChannelLayout::index, py::arg("name"))
      .def("__repr__", [](const ChannelLayout& l) { return "ChannelLayout('" + l.text() + "')"; });

  py::class_<Ifs> ifs(m, "Ifs", "An nD iterated function system with probabilities (Eq. 22).");
  ifs
      .def(py::init([](std::vector<AffineMap> maps, std::optional<std::vector<double>> probabilities,
                       const std::string& layout, const std::string& name) {
             return Ifs(name, ChannelLayout(layout), std::move(maps), probabilities.value_or(std::vector<double>{}));
           }),
           py::arg("maps"), py::arg("probabilities") = py::none(), py::arg("layout") = "xy",
           py::arg("name") = "untitled",
           "probabilities=None gives Jacobian-proportional probabilities (Eq. 46).")
      .def_property("name", &Ifs::name, &Ifs::set_name)
      .def_property("description", &Ifs::description, &Ifs::set_description)
      .def_property_readonly("layout", [](const Ifs& s) { return s.layout().text(); })
      .def_property_readonly("channel_names", [](const Ifs& s) { return s.layout().names(); })
      .def_property_readonly("dim", &Ifs::dim)
      .def_property_readonly("spatial_dims", &Ifs::spatial_dims)
      .def_property_readonly("maps", &Ifs::maps)
      .def_property_readonly("probabilities", [](const Ifs& s) {
        return py::array_t<double>(s.probabilities().size(), s.probabilities().data());
      })
      .def("__len__", &Ifs::size)
      .def("contraction_factors", [](const Ifs& s) { auto v = s.contraction_factors(); return py::array_t<double>(v.size(), v.data()); })
      .def("spatial_contraction_factors", [](const Ifs& s) { auto v = s.spatial_contraction_factors(); return py::array_t<double>(v.size(), v.data()); })
      .def("contraction_ratio", &Ifs::contraction_ratio, "max_i s_i (Eq. 10)")
      .def("average_log_contraction", &Ifs::average_log_contraction, "sum_i p_i log s_i (Eq. 14: < 0)")
      .def("lyapunov_exponent", &Ifs::lyapunov_exponent, py::arg("steps") = 20000, py::arg("seed") = 1)
      .def("classify", [](const Ifs& s) { return std::string(name_of(s.classify())); },
           "'hyperbolic', 'average-contractive', 'eventually-contractive' or 'divergent'")
      .def("summary", [](const Ifs& s) {
             // What `ifsforge info` prints, as plain Python values: no numpy (its import would
             // be most of a small info's time).
             const auto factors = s.contraction_factors();
             const auto fixed = s.fixed_points();
             const Classification kind = s.classify();
             py::dict out;
             out["name"] = s.name();
             out["layout"] = s.layout().text();
             out["channels"] = s.layout().names();
             py::list maps;
             double ratio = 0.0;  // max s_i (Eq. 10; Eq. 30 for polar maps)
             for (std::size_t i = 0; i < s.size(); ++i) {
               const AffineMap& m = s.map(i);
               py::list matrix;
               std::vector<double> offset(m.dim());
               for (int r = 0; r < m.dim(); ++r) {
                 std::vector<double> row(m.dim());
                 for (int c = 0; c < m.dim(); ++c) row[c] = m.a(r, c);
                 matrix.append(py::cast(row));
                 offset[r] = m.b(r);
               }
               const std::vector<double> point(fixed[i].begin(), fixed[i].begin() + s.dim());
               const bool none = std::any_of(point.begin(), point.end(), [](double v) { return std::isnan(v); });
               py::dict map;
               map["probability"] = s.probabilities()[i];
               if (s.polar() && s.polar_maps()[i]) {
                 // Its shadow's matrix would mislead: the map itself, and s_i of Eq. 30.
                 const PolarMap& p = *s.polar_maps()[i];
                 py::dict polar;
                 polar["center"] = p.center;
                 polar["k"] = p.k;
                 polar["F"] = p.f;
                 polar["G"] = p.g;
                 polar["winding"] = p.winding;
                 polar["f_bound"] = p.f_bound();
                 map["polar"] = polar;
                 map["contraction_factor"] = p.contraction();
                 ratio = std::max(ratio, p.contraction());
               } else {
                 map["matrix"] = matrix;
                 map["offset"] = offset;
                 map["contraction_factor"] = factors[i];
                 ratio = std::max(ratio, factors[i]);
                 map["determinant"] = m.determinant(s.spatial_dims());
               }
               map["fixed_point"] = none ? py::object(py::none()) : py::cast(point);
               maps.append(map);
             }
             out["maps"] = maps;
             out["classification"] = std::string(name_of(kind));
             out["contraction_ratio"] = ratio;
             out["average_log_contraction"] = s.average_log_contraction();
             // The linear parts of polar maps are only their shadows: no Lyapunov exponent.
             out["lyapunov_exponent"] = s.polar() ? py::object(py::none()) : py::cast(s.lyapunov_exponent());
             if (s.recurrent()) {
               py::list rows;
               for (std::size_t i = 0; i < s.size(); ++i) rows.append(py::cast(s.transitions().row(i)));
               out["transitions"] = rows;
             }
             if (kind != Classification::Divergent) {
               const Bounds b = s.attractor_bounds();
               py::dict bounds;
               for (int c = 0; c < s.dim(); ++c) bounds[py::str(s.layout().names()[c])] = std::vector<double>{b.lo[c], b.hi[c]};
               out["bounds"] = bounds;
             }
             return out;
           }, "What `ifsforge info` reports (maps, factors, fixed points, classification, transitions, bounds) as "
              "plain Python values")
      .def("require_attractor", &Ifs::require_attractor)
      .def("fixed_points", [](const Ifs& s) { return points_of(s.fixed_points(), s.dim()); })
      .def("start_point", [](const Ifs& s) { auto p = s.start_point(); return py::array_t<double>(s.dim(), p.data()); })
      .def("attractor_bounds", [](const Ifs& s, std::size_t samples) {
             py::gil_scoped_release release;
             Bounds b = s.attractor_bounds(samples);
             py::gil_scoped_acquire gil;
             return py::make_tuple(py::array_t<double>(b.lo.size(), b.lo.data()), py::array_t<double>(b.hi.size(), b.hi.data()));
           }, py::arg("samples") = 1u << 20, "(lo, hi) per channel")
      .def("sample_points", [](const Ifs& s, std::size_t count, std::uint64_t seed) {
             if (count > (std::size_t(1) << 28)) throw InputError("at most 2^28 sample points");
             require_sampler_handles("sample_points", s);
             py::array_t<double> out({static_cast<py::ssize_t>(count), static_cast<py::ssize_t>(s.dim())});
             double* data = out.mutable_data();
             {
               py::gil_scoped_release release;
               std::size_t k = 0;
               sample_attractor(s, count, seed, [&](const Point& p) {
                 std::copy(p.begin(), p.begin() + s.dim(), data + k++ * s.dim());
               });
             }
             return out;
           }, py::arg("count") = 200000, py::arg("seed") = 0,
           "count points of a seeded random iteration on the attractor, shape (count, dim): previews, "
           "scatter plots, instancing")
      .def("features", [](const Ifs& s) {
             const SystemFeatures f = system_features(s);
             py::dict out;
             out["recurrent"] = f.recurrent;
             out["polar"] = f.polar;
             out["average_contractive"] = f.average_contractive;
             out["overlapping"] = f.overlapping;
             out["condensation"] = f.condensation;
             out["spatial_dims"] = f.spatial_dims;
             out["determinant_sum"] = f.determinant_sum;
             return out;
           }, "what the system asks of an algorithm (model/capabilities.h): recurrent, polar, average_contractive "
              "(a map expands), overlapping (sum of |det| of the spatial blocks above 1), condensation, spatial_dims")
      .def_property_readonly("render_defaults", [](const Ifs& s) {
        const RenderDefaults& d = s.render_defaults();
        py::dict out;
        if (!d.window.empty()) out["window"] = d.window;
        if (!d.view.empty()) out["view"] = d.view;
        if (!d.algorithm.empty()) out["algorithm"] = d.algorithm;
        if (d.width > 0) out["size"] = py::make_tuple(d.width, d.height);
        return out;
      })
      .def("__repr__", [](const Ifs& s) {
        return "<Ifs '" + s.name() + "' " + s.layout().text() + ", " + std::to_string(s.size()) + " maps>";
      });

  m.def("jacobian_probabilities", [](const std::vector<AffineMap>& maps, int spatial_dims) {
    auto v = jacobian_probabilities(maps, spatial_dims);
    return py::array_t<double>(v.size(), v.data());
  }, py::arg("maps"), py::arg("spatial_dims"), "Eq. 46: p_i proportional to |det A_i|, floored at 1% of the largest.");
  m.def("contraction_factor_2d", &contraction_factor_2d, "Eq. 8-9.");
  bind_model_extensions(m, ifs);
  bind_polar_maps(m, ifs);
  m.def("sampler_capabilities", [] {
    py::dict out;
    for (const auto& [name, caps] : sampler_capabilities()) out[py::str(name)] = capability_dict(caps);
    return out;
  }, "{sampler: {capability: bool}} for sample_points and preview_cloud (model/capabilities.h)");
}

}  // namespace ifsforge::python
