// Vector IFS: instance lists (vector recursive rendering), addresses (string rewriting, TSA),
// primitives and the raster drawing of instance lists.
#include "bindings.h"
#include "ifsforge/core/error.h"
#include "ifsforge/vector/addresses.h"
#include "ifsforge/vector/draw.h"
#include "ifsforge/io/primitive_spec.h"
#include "ifsforge/io/address_csv.h"
#include "ifsforge/vector/instances.h"

namespace ifsforge::python {
namespace {

/// A read-only numpy view of `data` that keeps `owner` (the Python object holding it) alive.
template <typename T>
py::array_t<T> view(const py::object& owner, const T* data, std::vector<py::ssize_t> shape) {
  py::array_t<T> out(shape, data, owner);
  py::detail::array_proxy(out.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return out;
}

std::vector<Primitive> primitives_from(const py::object& spec) {
  if (py::isinstance<py::str>(spec)) return parse_primitives(spec.cast<std::string>());
  if (py::isinstance<Primitive>(spec)) return {spec.cast<Primitive>()};
  std::vector<Primitive> out;
  for (const py::handle item : spec) {
    if (py::isinstance<Primitive>(item))
      out.push_back(item.cast<Primitive>());
    else
      out.push_back(parse_primitive(py::str(item).cast<std::string>()));
  }
  return out;
}

/// The instance list as one numpy structured array (a copy), one record per instance.
py::array structured(const InstanceList& l) {
  const int depth = std::max(1, l.addresses.depth);
  py::list fields;
  fields.append(py::make_tuple("position", "<f4", py::make_tuple(3)));
  fields.append(py::make_tuple("frame", "<f4", py::make_tuple(3, 3)));
  fields.append(py::make_tuple("scale", "<f4"));
  fields.append(py::make_tuple("primitive", "<u2"));
  fields.append(py::make_tuple("color", "<f4", py::make_tuple(4)));
  fields.append(py::make_tuple("probability", "<f8"));
  fields.append(py::make_tuple("length", "u1"));
  fields.append(py::make_tuple("address", "<u2", py::make_tuple(depth)));
  const py::dtype dtype = py::dtype::from_args(fields);
  py::array out(dtype, std::vector<py::ssize_t>{static_cast<py::ssize_t>(l.size())});
  const py::dict offsets = dtype.attr("fields");
  auto offset = [&](const char* name) { return offsets[name].cast<py::tuple>()[1].cast<std::size_t>(); };
  const std::size_t o_pos = offset("position"), o_frame = offset("frame"), o_scale = offset("scale"),
                    o_prim = offset("primitive"), o_color = offset("color"), o_prob = offset("probability"),
                    o_len = offset("length"), o_addr = offset("address");
  const std::size_t item = static_cast<std::size_t>(dtype.itemsize());
  char* base = static_cast<char*>(out.mutable_data());
  for (std::size_t i = 0; i < l.size(); ++i) {
    char* r = base + i * item;
    std::memcpy(r + o_pos, l.positions[i].data(), 12);
    std::memcpy(r + o_frame, l.frames[i].data(), 36);
    std::memcpy(r + o_scale, &l.scales[i], 4);
    std::memcpy(r + o_prim, &l.primitive[i], 2);
    std::memcpy(r + o_color, l.colors[i].data(), 16);
    std::memcpy(r + o_prob, &l.addresses.probabilities[i], 8);
    std::memcpy(r + o_len, &l.addresses.lengths[i], 1);
    if (l.addresses.depth > 0) std::memcpy(r + o_addr, l.addresses.address(i), 2 * l.addresses.depth);
  }
  return out;
}

std::optional<std::vector<double>> optional_vector(const py::object& o) {
  if (o.is_none()) return std::nullopt;
  return o.cast<std::vector<double>>();
}

}  // namespace

void bind_vector(py::module_& m) {
  add_choices<Normalization>(m, "normalization");
  add_choices<ColorSource>(m, "color_source");
  py::class_<Primitive>(m, "Primitive",
                        "A graphics primitive placed by vector IFS instances, in the instance's frame (x along the "
                        "vector, one unit = its length d).")
      .def(py::init(&parse_primitive), py::arg("spec"),
           "'line', 'circle', 'triangle', 'square' (each also '-outline' but line), 'sphere', 'box', 'cone', "
           "'cylinder', 'torus' or 'mesh:PATH'.")
      .def_property_readonly("name", &Primitive::name)
      .def_property_readonly("flat", &Primitive::flat, "a shape of the plane (line, circle, triangle, square)")
      .def_property_readonly("bounding_radius", &Primitive::bounding_radius, "in units of d")
      .def("mesh", [](const Primitive& p, int segments) { return mesh_dict(primitive_mesh(p, segments)); },
           py::arg("segments") = 32, "{'positions', 'normals', 'triangles'} in the frame of the primitive")
      .def("__repr__", [](const Primitive& p) { return "Primitive('" + p.name() + "')"; });
  m.def("primitive_names", &builtin_primitive_names, "names of the built-in primitives");

  py::class_<AddressTable>(m, "AddressTable",
                           "Leaf addresses in depth-first order: map indices from the outermost map in "
                           "(a0 picks the first-level copy).")
      .def("__len__", &AddressTable::size)
      .def_readonly("depth", &AddressTable::depth, "columns of digits: the longest address")
      .def_property_readonly("digits", [](py::object self) {
        const auto& t = self.cast<const AddressTable&>();
        return view(self, t.digits.data(), {static_cast<py::ssize_t>(t.size()), static_cast<py::ssize_t>(t.depth)});
      }, "(n, depth) uint16; 65535 past each address's length")
      .def_property_readonly("lengths", [](py::object self) {
        const auto& t = self.cast<const AddressTable&>();
        return view(self, t.lengths.data(), {static_cast<py::ssize_t>(t.size())});
      })
      .def_property_readonly("probabilities", [](py::object self) {
        const auto& t = self.cast<const AddressTable&>();
        return view(self, t.probabilities.data(), {static_cast<py::ssize_t>(t.size())});
      }, "product of the map probabilities along each address (the piece's invariant measure)")
      .def("strings", [](const AddressTable& t) {
        std::vector<std::string> out;
        out.reserve(t.size());
        for (std::size_t i = 0; i < t.size(); ++i) out.push_back(t.to_string(i));
        return out;
      }, "'a0.a1.....' per leaf")
      .def("__getitem__", [](const AddressTable& t, std::size_t i) {
        if (i >= t.size()) throw py::index_error("address index out of range");
        return std::vector<std::uint16_t>(t.address(i), t.address(i) + t.lengths[i]);
      });

  py::class_<AddressLeaves>(m, "AddressLeaves", "What the tesseral synecdoche algorithm plots: addresses and points.")
      .def("__len__", [](const AddressLeaves& a) { return a.addresses.size(); })
      .def_readonly("addresses", &AddressLeaves::addresses)
      .def_property_readonly("points", [](py::object self) {
        const auto& a = self.cast<const AddressLeaves&>();
        return view(self, a.points.data(), {static_cast<py::ssize_t>(a.addresses.size()), static_cast<py::ssize_t>(a.dim)});
      }, "(n, dim) float64: w_address(start) in every channel");

  py::class_<InstanceList>(m, "InstanceList",
                           "One primitive per leaf of vector recursive rendering (5.8.2), in address order. Array "
                           "properties are read-only views; to_numpy() gives one structured array.")
      .def("__len__", &InstanceList::size)
      .def_readonly("name", &InstanceList::name)
      .def_readonly("spatial_dims", &InstanceList::spatial_dims)
      .def_readonly("primitives", &InstanceList::primitives)
      .def_readonly("addresses", &InstanceList::addresses)
      .def_property_readonly("positions", [](py::object self) {
        const auto& l = self.cast<const InstanceList&>();
        return view(self, l.positions.data()->data(), {static_cast<py::ssize_t>(l.size()), 3});
      }, "(n, 3) float32: q0' (z = 0 for 2D systems)")
      .def_property_readonly("frames", [](py::object self) {
        const auto& l = self.cast<const InstanceList&>();
        return view(self, l.frames.data()->data(), {static_cast<py::ssize_t>(l.size()), 3, 3});
      }, "(n, 3, 3) float32: rows e1 (along the vector), e2, e3 = e1 x e2")
      .def_property_readonly("scales", [](py::object self) {
        const auto& l = self.cast<const InstanceList&>();
        return view(self, l.scales.data(), {static_cast<py::ssize_t>(l.size())});
      }, "(n,) float32: d of Eq. 60")
      .def_property_readonly("primitive", [](py::object self) {
        const auto& l = self.cast<const InstanceList&>();
        return view(self, l.primitive.data(), {static_cast<py::ssize_t>(l.size())});
      }, "(n,) uint16: index into primitives")
      .def_property_readonly("colors", [](py::object self) {
        const auto& l = self.cast<const InstanceList&>();
        return view(self, l.colors.data()->data(), {static_cast<py::ssize_t>(l.size()), 4});
      }, "(n, 4) float32: sRGB + alpha in [0, 1]")
      .def("bounds", [](const InstanceList& l) -> py::object {
        std::array<double, 3> lo, hi;
        if (!l.bounds(lo, hi)) return py::none();
        return py::make_tuple(lo, hi);
      }, "(lo, hi) of the box holding every instance's bounding ball, or None")
      .def("to_numpy", &structured,
           "A structured array: position (3,) f4, frame (3, 3) f4, scale f4, primitive u2, color (4,) f4, "
           "probability f8, length u1, address (depth,) u2.")
      .def("__repr__", [](const InstanceList& l) {
        return "<InstanceList '" + l.name + "' " + std::to_string(l.size()) + " instances, depth " +
               std::to_string(l.addresses.depth) + ">";
      });

  options_class<InstanceOptions>(m, "InstanceOptions", "The settings of instances() (keywords of the same names).")
      .def_readwrite("depth", &InstanceOptions::depth, "recursion depth L (0: default_instance_depth)")
      .def_readwrite("min_probability", &InstanceOptions::min_probability, "pv of the TSA (5.7)")
      .def_property("primitives", [](const InstanceOptions& o) {
                      std::vector<std::string> names;
                      for (const auto& p : o.primitives) names.push_back(p.name());
                      return names;
                    },
                    [](InstanceOptions& o, const py::object& spec) { o.primitives = primitives_from(spec); },
                    "'sphere', 'sphere,box,cone', a list of names or Primitives")
      .def_property("normalization", [](const InstanceOptions& o) { return std::string(name_of(o.normalization)); },
                    [](InstanceOptions& o, const std::string& n) { o.normalization = parse_name<Normalization>(n); },
                    "proportional (Eq. 60) or constant")
      .def_property("normalisation",  // the old spelling (deprecated), kept for one release
                    [](const InstanceOptions& o) { return std::string(name_of(o.normalization)); },
                    [](InstanceOptions& o, const std::string& n) {
                      if (PyErr_WarnEx(PyExc_DeprecationWarning, "normalisation is deprecated; use normalization", 1) != 0)
                        throw py::error_already_set();
                      o.normalization = parse_name<Normalization>(n);
                    },
                    "deprecated spelling of normalization")
      .def_readwrite("scale_factor", &InstanceOptions::scale_factor, "sf of Eq. 60")
      .def_readwrite("length", &InstanceOptions::length, "constant normalization: the vector length (0: automatic)")
      .def_readwrite("base_point", &InstanceOptions::base_point, "q0 (empty: the centre of the attractor's bounds)")
      .def_readwrite("base_vector", &InstanceOptions::base_vector, "q1 - q0 (empty: (R, 0[, 0]))")
      .def_readwrite("base_up", &InstanceOptions::base_up, "the frame's second axis before mapping (empty: y)")
      .def_property("color_source", [](const InstanceOptions& o) { return std::string(name_of(o.color_source)); },
                    [](InstanceOptions& o, const std::string& c) { o.color_source = parse_name<ColorSource>(c); },
                    "auto, channels, first-map, last-map or constant")
      .def_readwrite("normalize_colors", &InstanceOptions::normalize_colors, "Eq. 101's stretch of each color channel")
      .def_readwrite("color", &InstanceOptions::color, "RGBA for color_source constant")
      .def_readwrite("threads", &InstanceOptions::threads, "0: every core; the list never depends on it")
      .def_property("progress", [](const InstanceOptions&) { return py::none(); },
                    [](InstanceOptions& o, const py::object& f) { o.progress = wrap_progress(f); },
                    "progress(fraction) returning False cancels (write-only)");

  m.def("instances",
        [](const Ifs& ifs, const py::object& depth, const py::kwargs& kwargs) {
          py::dict given(kwargs);
          add_option(given, "depth", depth);
          const InstanceOptions o = options_from<InstanceOptions>("instances", given);
          py::gil_scoped_release release;
          return instances(ifs, o);
        },
        py::arg("ifs"), py::arg("depth") = py::none(),
        "The InstanceOptions given as keywords. "
        "Vector recursive rendering (5.8.2): the instance list of a system. depth=0 picks the largest L with "
        "N^L <= 50000. primitives: 'sphere', 'sphere,box,cone' or a list; the k channel (Eq. 99, 107) picks "
        "one (rounded, modulo the list). normalization: 'proportional' (d = sf |q1 - q0|, Eq. 60) or "
        "'constant' (d = length). min_probability: pv of the TSA (5.7). color_source: auto, channels, "
        "first-map, last-map or constant (color). normalize_colors: Eq. 101's stretch of each color channel over "
        "the attractor (False: the values as given, clamped to [0, 1]).");
  m.def("default_instance_depth", &default_instance_depth, py::arg("maps"), py::arg("max_instances") = 50000);

  add_choices<AddressSpelling>(m, "spelling");
  m.def("string_rewriting",
        [](const Ifs& ifs, int depth, const std::string& spelling) {
          return string_rewriting(ifs, depth, parse_name<AddressSpelling>(spelling, "spelling"));
        },
        py::arg("ifs"), py::arg("depth"), py::arg("spelling") = name_of(AddressSpelling::Digits),
        "The seed's string-rewriting algorithm (5.6): the N^depth addresses in its order, spelled "
        "'a0.a1...' (digits) or 'w2w1...' (seed).");
  m.def("tesseral_synecdoche",
        [](const Ifs& ifs, int depth, double min_probability, const py::object& start, int threads, const py::object& progress) {
          const std::vector<double> s = optional_vector(start).value_or(std::vector<double>{});
          ProgressCallback p = wrap_progress(progress);
          py::gil_scoped_release release;
          return tesseral_synecdoche(ifs, depth, min_probability, s, threads, p);
        },
        py::arg("ifs"), py::arg("depth"), py::arg("min_probability") = 0.0, py::arg("start") = py::none(),
        py::arg("threads") = 0, py::arg("progress") = py::none(),
        "The tesseral synecdoche algorithm (5.7): leaves at depth or below probability pv, depth-first.");
  m.def("apply_address", [](const Ifs& ifs, const std::vector<std::uint16_t>& address, const std::vector<double>& point) {
          if (static_cast<int>(point.size()) != ifs.dim())
            throw InputError("the point needs " + std::to_string(ifs.dim()) + " coordinates");
          Point p{};
          std::copy(point.begin(), point.end(), p.begin());
          const Point q = apply_address(ifs, address.data(), static_cast<int>(address.size()), p);
          return std::vector<double>(q.begin(), q.begin() + ifs.dim());
        }, py::arg("ifs"), py::arg("address"), py::arg("point"), "w_a0(w_a1(...w_aL-1(point)))");
  m.def("count_leaves", &count_leaves, py::arg("ifs"), py::arg("depth"), py::arg("min_probability") = 0.0);
  m.def("write_address_csv", [](const std::string& path, const AddressTable& t) {
          py::gil_scoped_release release;
          write_address_csv(path, t);
        }, py::arg("path"), py::arg("addresses"), "CSV: index,address,length,probability (atomic).");

  options_class<DrawOptions>(m, "DrawOptions", "The settings of draw_instances() (keywords of the same names).")
      .def_readwrite("width", &DrawOptions::width)
      .def_readwrite("height", &DrawOptions::height, "draw_instances(): default the width")
      .def_property("window", [](const DrawOptions& o) { return window_tuple(o.window); },
                    [](DrawOptions& o, const std::optional<std::array<double, 4>>& w) { o.window = window_argument(w); },
                    "(xmin, ymin, xmax, ymax); None: the instances' projected bounds")
      .def_property("view", [](const DrawOptions& o) { return std::array<double, 2>{o.view.yaw, o.view.pitch}; },
                    [](DrawOptions& o, const std::array<double, 2>& v) { o.view = View{v[0], v[1]}; },
                    "(yaw, pitch) in degrees, for 3D lists")
      .def_readwrite("background", &DrawOptions::background, "RGBA")
      .def_readwrite("supersample", &DrawOptions::supersample, "samples per pixel along each axis (1..8)")
      .def_readwrite("threads", &DrawOptions::threads, "0: every core; the image never depends on it");
  m.def("draw_instances",
        [](const InstanceList& list, const py::object& width, const py::object& height, const py::kwargs& kwargs) {
          py::dict given(kwargs);
          add_option(given, "width", width);
          add_option(given, "height", height);
          DrawOptions o = options_from<DrawOptions>("draw_instances", given);
          if (!given.contains("height") || given["height"].is_none()) o.height = o.width;
          Image image;
          {
            py::gil_scoped_release release;
            image = draw_instances(list, o);
          }
          return image_to_numpy(image);
        },
        py::arg("instances"), py::arg("width") = py::none(), py::arg("height") = py::none(),
        "RGBA (h, w, 4) float32 picture of the instances without POV-Ray (2D: list order; 3D: flat-shaded, far to near).");
}

}  // namespace ifsforge::python
