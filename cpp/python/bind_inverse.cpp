// The inverse problem (seed chapter 4): collage distance, automatic fitting.
#include "bindings.h"
#include "ifsforge/core/error.h"
#include "ifsforge/inverse/address_of.h"
#include "ifsforge/inverse/collage.h"
#include "ifsforge/inverse/fit.h"
#include "ifsforge/inverse/fit_3d.h"
#include "ifsforge/inverse/fit_color.h"
#include "ifsforge/render/tops.h"

namespace ifsforge::python {

/// A bool (h, w) array is taken as it is; any other array is a picture whose foreground is
/// found by ifsforge::foreground.
PixelSet pixel_set_from_numpy(const py::array& array, double threshold) {
  if (array.dtype().kind() == 'b') {
    if (array.ndim() != 2) throw InputError("a boolean target must be a (height, width) array");
    auto a = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(array);
    PixelSet s{static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)), {}};
    s.cells.assign(a.data(), a.data() + a.size());
    return s;
  }
  return foreground(image_from_numpy(array), threshold);
}

py::array_t<bool> pixel_set_to_numpy(const PixelSet& s) {
  py::array_t<bool> out({s.height, s.width});
  std::copy(s.cells.begin(), s.cells.end(), out.mutable_data());
  return out;
}

namespace {

py::dict report_dict(const CollageReport& r) {
  py::dict d;
  d["distance_pixels"] = r.distance_pixels;
  d["distance"] = r.distance;
  d["contraction"] = r.contraction;
  d["bound"] = r.bound;
  d["bound_pixels"] = r.bound_pixels;
  d["target_pixels"] = r.target_pixels;
  d["collage_pixels"] = r.collage_pixels;
  d["window"] = py::make_tuple(r.window.xmin, r.window.ymin, r.window.xmax, r.window.ymax);
  return d;
}

std::optional<Window> window_from(const std::optional<std::vector<double>>& w) {
  if (!w) return std::nullopt;
  if (w->size() != 4) throw InputError("window expects 4 numbers: xmin ymin xmax ymax");
  return Window{(*w)[0], (*w)[1], (*w)[2], (*w)[3]};
}

/// The frame `render` uses: the window given, else the system's render.window, else the attractor's.
Frame frame_of(const Ifs& ifs, int width, int height, const std::optional<std::vector<double>>& window) {
  std::optional<Window> w = window_from(window);
  const auto& saved = ifs.render_defaults().window;
  if (!w && saved.size() == 4) w = Window{saved[0], saved[1], saved[2], saved[3]};
  return Frame::fit(ifs, width, height, w);
}

/// The spatial block of every map of `ifs` (extra channels never move the points): a fit's start.
std::vector<AffineMap> spatial_maps(const Ifs& ifs) {
  const int dim = ifs.spatial_dims();
  std::vector<AffineMap> out;
  for (const AffineMap& m : ifs.maps()) {
    AffineMap spatial(dim);
    for (int r = 0; r < dim; ++r) {
      for (int c = 0; c < dim; ++c) spatial.a(r, c) = m.a(r, c);
      spatial.b(r) = m.b(r);
    }
    out.push_back(spatial);
  }
  return out;
}

py::dict fit_result_dict(const FitResult& r) {
  py::dict d;
  d["system"] = r.system;
  d["iou"] = r.iou;
  d["proxy"] = r.proxy;
  d["evaluations"] = r.evaluations;
  d["restarts"] = r.restarts;
  d["time_limited"] = r.time_limited;
  return d;
}

/// A bool (nx, ny, nz) array laid on cubic voxels of `voxel_size` from `origin` (as
/// read_voxel_target returns it and Volume.to_dense lays it out).
VoxelSet voxel_set_from_numpy(const py::array& mask, const std::array<double, 3>& origin, double voxel_size) {
  if (mask.ndim() != 3) throw InputError("a 3D target is a (nx, ny, nz) array, got " + std::to_string(mask.ndim()) + " dimensions");
  if (!(voxel_size > 0)) throw InputError("voxel_size must be positive");
  auto a = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(mask);
  VoxelSet s;
  s.grid.origin = origin;
  s.grid.voxel_size = voxel_size;
  for (int k = 0; k < 3; ++k) s.grid.dims[k] = static_cast<int>(a.shape(k));
  s.cells.assign(a.size(), 0);
  const bool* p = a.data();
  for (int i = 0; i < s.grid.dims[0]; ++i)
    for (int j = 0; j < s.grid.dims[1]; ++j)
      for (int k = 0; k < s.grid.dims[2]; ++k) s.cells[s.index(i, j, k)] = *p++;
  return s;
}

void bind_fit_extensions(py::module_& m) {
  options_class<ColorFitOptions>(m, "ColorFitOptions", "The settings of fit_color() (keywords of the same names).")
      .def_readwrite("max_contraction", &ColorFitOptions::max_contraction,
                     "every map's contraction factor on (x, y, r, g, b) stays at most this")
      .def_readwrite("positional", &ColorFitOptions::positional, "color rows may depend on x, y")
      .def_readwrite("mixing", &ColorFitOptions::mixing, "a channel's row may read the other channels")
      .def_readwrite("tolerance", &ColorFitOptions::tolerance,
                     "color_foreground: a channel difference from the border's color above this is shape");
  m.def("has_color", [](const py::array& picture) { return has_color(image_from_numpy(picture)); }, py::arg("picture"),
        "True when the picture has three or more channels that are not all equal.");
  m.def("color_foreground", [](const py::array& picture, double tolerance) {
    return pixel_set_to_numpy(color_foreground(image_from_numpy(picture), tolerance));
  }, py::arg("picture"), py::arg("tolerance") = ColorFitOptions().tolerance,
        "bool (h, w): the pixels whose color differs from the border's usual color by more than `tolerance` "
        "in some channel.");
  m.def("fit_color", [](const Ifs& shape_system, const py::array& picture, const py::object& shape, const py::kwargs& kwargs) {
    const ColorFitOptions o = options_from<ColorFitOptions>("fit_color", kwargs);
    const Image image = image_from_numpy(picture);
    const PixelSet s = shape.is_none() ? color_foreground(image, o.tolerance) : pixel_set_from_numpy(shape, 0.5);
    ColorFitResult r;
    {
      py::gil_scoped_release release;
      r = fit_color(shape_system, image, s, o);
    }
    py::dict d;
    d["system"] = r.system;
    d["collage_error"] = py::make_tuple(r.collage_error[0], r.collage_error[1], r.collage_error[2]);
    d["samples"] = r.samples;
    return d;
  }, py::arg("shape_system"), py::arg("picture"), py::arg("shape") = py::none(),
        "Seed Fig. 4.3, one collage per channel: the xy system `shape_system` (fitted to the picture's shape) "
        "extended to xy+rgb, each map's color rows (C_i (r, g, b) + g_i . (x, y) + o_i) solved by least "
        "squares so that the picture's color at w_i(p) matches the color map of its color at p; color maps "
        "contractive. shape: bool (h, w), default color_foreground(picture). The ColorFitOptions given as "
        "keywords. Returns a dict: system, collage_error (RMS per channel r, g, b, in [0, 1] units), samples.");
  options_class<Fit3dOptions>(m, "Fit3dOptions", "The settings of fit_3d(); its keywords are these fields, their defaults these.")
      .def_readwrite("maps", &Fit3dOptions::maps, "N, the number of maps")
      .def_readwrite("raster", &Fit3dOptions::raster, "voxels along the target's longest side during the search")
      .def_readwrite("refine_raster", &Fit3dOptions::refine_raster, "voxels along the longest side in the last search")
      .def_readwrite("max_contraction", &Fit3dOptions::max_contraction, "every map's s_i stays at most this")
      .def_readwrite("overlap_weight", &Fit3dOptions::overlap_weight, "weight of the copies' overlap in the collage proxy")
      .def_readwrite("restarts", &Fit3dOptions::restarts, "CMA-ES runs, each from its own initial collage")
      .def_readwrite("generations", &Fit3dOptions::generations, "CMA-ES generations per run on the collage proxy")
      .def_readwrite("attractor_generations", &Fit3dOptions::attractor_generations,
                     "generations per run on the attractor after the collage proxy")
      .def_readwrite("final_generations", &Fit3dOptions::final_generations,
                     "generations of the last search, on the attractor's IoU at refine_raster")
      .def_readwrite("time_limit", &Fit3dOptions::time_limit, "seconds; 0: none (only then is the run independent of speed)")
      .def_readwrite("seed", &Fit3dOptions::seed)
      .def_readwrite("threads", &Fit3dOptions::threads, "0: every core; the result never depends on it")
      .def_property("progress", [](const Fit3dOptions&) { return py::none(); },
                    [](Fit3dOptions& o, const py::object& f) { o.progress = wrap_progress(f); },
                    "progress(fraction) returning False cancels (write-only)")
      .def_property("start", [](const Fit3dOptions&) { return py::none(); },
                    [](Fit3dOptions& o, const Ifs& start) { o.start = spatial_maps(start); },
                    "a system of `maps` maps (an earlier fit's) to start the last search from, skipping the "
                    "restarts (write-only)");
  m.def("fit_3d", [](const py::array& mask, std::array<double, 3> origin, double voxel_size, const py::kwargs& kwargs) {
    const Fit3dOptions o = options_from<Fit3dOptions>("fit_3d", kwargs);
    const VoxelSet t = voxel_set_from_numpy(mask, origin, voxel_size);
    FitResult r;
    {
      py::gil_scoped_release release;
      r = fit_3d(t, o);
    }
    return fit_result_dict(r);
  }, py::arg("mask"), py::arg("origin") = std::array<double, 3>{0, 0, 0}, py::arg("voxel_size") = 1.0,
        "An xyz IFS whose attractor fills the target: mask bool (nx, ny, nz), voxel (i, j, k) covering "
        "origin + [i, i+1] x [j, j+1] x [k, k+1] * voxel_size (read_voxel_target's dict can be passed as "
        "keywords). CMA-ES restarts on a 3D collage proxy (Eq. 41) over a `raster`-voxel grid, then the "
        "attractor's IoU on a `refine_raster` grid; the Fit3dOptions given as keywords. Returns a dict: system, "
        "iou (on the refinement grid), proxy, evaluations, restarts, time_limited. Identical for a given seed "
        "and any thread count unless time_limit cut it short.");
  m.def("attractor_iou_3d", [](const Ifs& ifs, const py::array& mask, std::array<double, 3> origin, double voxel_size,
                               std::uint64_t seed) {
    const VoxelSet t = voxel_set_from_numpy(mask, origin, voxel_size);
    py::gil_scoped_release release;
    return attractor_iou_3d(ifs, t, seed);
  }, py::arg("ifs"), py::arg("mask"), py::arg("origin") = std::array<double, 3>{0, 0, 0}, py::arg("voxel_size") = 1.0,
        py::arg("seed") = 0, "Intersection over union of the attractor (chaos game) of an xyz system and a voxel target.");
}

}  // namespace

void bind_inverse(py::module_& m) {
  bind_fit_extensions(m);
  m.def("foreground", [](const py::array& image, double threshold) {
    return pixel_set_to_numpy(foreground(image_from_numpy(image), threshold));
  }, py::arg("image"), py::arg("threshold") = 0.5,
        "bool (h, w): the picture's shape, i.e. the pixels on the other side of `threshold` from the border's "
        "usual value (luminance times alpha).");
  m.def("hausdorff_distance", [](const py::array& a, const py::array& b) {
    return hausdorff_distance(pixel_set_from_numpy(a, 0.5), pixel_set_from_numpy(b, 0.5));
  }, py::arg("a"), py::arg("b"), "Eq. 12 between two bool (h, w) pixel sets, in pixels (exact distance transforms).");
  m.def("collage_distance", [](const Ifs& ifs, const py::array& target, std::optional<std::vector<double>> window,
                               double threshold) {
    const PixelSet t = pixel_set_from_numpy(target, threshold);
    CollageReport r;
    {
      py::gil_scoped_release release;
      r = collage_distance(ifs, t, window_from(window));
    }
    return report_dict(r);
  }, py::arg("ifs"), py::arg("target"), py::arg("window") = py::none(), py::arg("threshold") = 0.5,
        "Collage theorem (Eq. 41-42): the Hausdorff distance between the target (a bool mask or a picture) and "
        "the union of its images under the maps, and the bound distance / (1 - s) on the distance from the "
        "target to the attractor. The target lies on `window` (default: the attractor's frame at the "
        "target's size; or the system's render.window). Returns a dict: distance_pixels, distance, contraction, bound, bound_pixels, "
        "target_pixels, collage_pixels, window.");
  py::class_<CollageTarget>(m, "CollageTarget",
                            "A target prepared for many collage distances (a design's live value): the distance "
                            "transform to it is computed once.")
      .def(py::init([](const py::array& target, double threshold) {
        return CollageTarget(pixel_set_from_numpy(target, threshold));
      }), py::arg("target"), py::arg("threshold") = 0.5)
      .def("distance", [](const CollageTarget& t, const Ifs& ifs, std::optional<std::vector<double>> window) {
        CollageReport r;
        {
          py::gil_scoped_release release;
          r = t.distance(ifs, window_from(window));
        }
        return report_dict(r);
      }, py::arg("ifs"), py::arg("window") = py::none(), "collage_distance(ifs, target, window), the same dict")
      .def_property_readonly("mask", [](const CollageTarget& t) { return pixel_set_to_numpy(t.pixels()); });
  m.def("collage_mask", [](const Ifs& ifs, const py::array& target, std::optional<std::vector<double>> window,
                           double threshold) {
    const PixelSet t = pixel_set_from_numpy(target, threshold);
    return pixel_set_to_numpy(collage_pixels(t, pixel_maps(ifs, target_frame(ifs, t, window_from(window))), 0));
  }, py::arg("ifs"), py::arg("target"), py::arg("window") = py::none(), py::arg("threshold") = 0.5,
        "bool (h, w): the collage U w_i(target) on the target's grid (what lands outside is dropped).");
  options_class<FitOptions>(m, "FitOptions", "The settings of fit(); its keywords are these fields, their defaults these.")
      .def_readwrite("maps", &FitOptions::maps, "N, the number of maps")
      .def_readwrite("raster", &FitOptions::raster, "cells along the target's long side during the search")
      .def_readwrite("max_contraction", &FitOptions::max_contraction, "every map's s_i (Eq. 8-9) stays at most this")
      .def_readwrite("overlap_weight", &FitOptions::overlap_weight, "weight of the copies' overlap in the collage proxy")
      .def_readwrite("restarts", &FitOptions::restarts, "CMA-ES runs, each from its own initial collage")
      .def_readwrite("generations", &FitOptions::generations, "CMA-ES generations per run")
      .def_readwrite("attractor_generations", &FitOptions::attractor_generations,
                     "generations per run on the attractor after the collage proxy")
      .def_readwrite("refine_generations", &FitOptions::refine_generations, "generations of the final refinement")
      .def_readwrite("final_generations", &FitOptions::final_generations,
                     "generations of the last search, on the attractor's IoU at the picture's resolution")
      .def_readwrite("refine_raster", &FitOptions::refine_raster,
                     "cells along the long side during the refinement (at most the picture's)")
      .def_readwrite("time_limit", &FitOptions::time_limit,
                     "seconds; 0: none (only then is the run independent of speed)")
      .def_readwrite("seed", &FitOptions::seed)
      .def_readwrite("threads", &FitOptions::threads, "0: every core; the result never depends on it")
      .def_property("progress", [](const FitOptions&) { return py::none(); },
                    [](FitOptions& o, const py::object& f) { o.progress = wrap_progress(f); },
                    "progress(fraction) returning False cancels (write-only)")
      .def_property("start", [](const FitOptions&) { return py::none(); },
                    [](FitOptions& o, const Ifs& start) { o.start = spatial_maps(start); },
                    "a system of `maps` maps (an earlier fit's) to start the last search from, skipping the "
                    "restarts (write-only)");
  m.def("fit", [](const py::array& target, double threshold, const py::kwargs& kwargs) {
    const FitOptions o = options_from<FitOptions>("fit", kwargs);
    const PixelSet t = pixel_set_from_numpy(target, threshold);
    FitResult r;
    {
      py::gil_scoped_release release;
      r = fit_ifs(t, o);
    }
    return fit_result_dict(r);
  }, py::arg("target"), py::arg("threshold") = 0.5,
        "The FitOptions given as keywords. "
        "An IFS of `maps` maps whose attractor resembles the target (a bool mask or a picture): CMA-ES "
        "restarts on a collage proxy over a `raster`-cell grid, then refinement on the attractor. The system "
        "carries render.window and the target's size. Returns a dict: system, iou (on the search raster), "
        "proxy, evaluations, restarts, time_limited. Identical for a given seed and any thread count unless "
        "time_limit cut it short.");
  py::reinterpret_borrow<py::class_<Ifs>>(m.attr("Ifs"))
      .def("address_of", [](const Ifs& ifs, const std::vector<double>& point, int depth) {
        PointAddresses r;
        {
          py::gil_scoped_release release;
          r = address_of(ifs, point, depth);
        }
        return py::make_tuple(r.addresses, r.distance);
      }, py::arg("point"), py::arg("depth") = 8,
      "(addresses, distance): the depth-`depth` addresses (lists of 0-based map indices, outermost map "
      "first) of the pieces that may hold the attractor point nearest to `point`, by the hierarchy of "
      "bounding boxes (seed 3.3.1), and the distance to the nearest attractor point found.");
  options_class<TopsOptions>(m, "TopsOptions", "The settings of tops() and tops_warp() (keywords of the same names).")
      .def_readwrite("width", &TopsOptions::width)
      .def_readwrite("height", &TopsOptions::height)
      .def_property("iterations", [](const TopsOptions& o) { return o.iterations; },
                    [](TopsOptions& o, long long v) { o.iterations = count_argument(v, "iterations"); },
                    "chaos-game points (0: 16 per pixel, Eq. 44)")
      .def_readwrite("seed", &TopsOptions::seed);
  m.def("tops", [](const Ifs& ifs, const py::object& width, const py::object& height,
                   std::optional<std::vector<double>> window, const py::kwargs& kwargs) {
    py::dict given(kwargs);
    add_option(given, "width", width);
    add_option(given, "height", height);
    const TopsOptions o = options_from<TopsOptions>("tops", given);
    Tops t;
    {
      py::gil_scoped_release release;
      t = tops(ifs, frame_of(ifs, o.width, o.height, window), o);
    }
    py::array_t<std::uint8_t> digits({o.height, o.width, kTopsDepth});
    auto d = digits.mutable_unchecked<3>();
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x)
        for (int k = 0; k < kTopsDepth; ++k)
          d(y, x, k) = static_cast<std::uint8_t>((t.codes[std::size_t(y) * o.width + x] >> (60 - 4 * k)) & 15);
    PixelSet covered{o.width, o.height, t.covered};
    return py::make_tuple(digits, pixel_set_to_numpy(covered));
  }, py::arg("ifs"), py::arg("width") = py::none(), py::arg("height") = py::none(), py::arg("window") = py::none(),
        "Fractal tops (seed 3.3.5): (digits uint8 (h, w, 16), covered bool (h, w)): per pixel the largest "
        "address (outermost map first) among the chaos game's points in it; the TopsOptions given as keywords. "
        "window: default the system's render.window, else the attractor's frame.");
  m.def("tops_warp", [](const Ifs& f, const py::array& picture, const Ifs& g, const py::object& width,
                        const py::object& height, const py::kwargs& kwargs) {
    py::dict given(kwargs);
    add_option(given, "width", width);
    add_option(given, "height", height);
    const TopsOptions o = options_from<TopsOptions>("tops_warp", given);
    const Image image = image_from_numpy(picture);
    Image out;
    {
      py::gil_scoped_release release;
      const Frame ff = frame_of(f, image.width, image.height, std::nullopt);
      out = tops_warp(f, ff, image, g, frame_of(g, o.width, o.height, std::nullopt), o);
    }
    return image_to_numpy(out);
  }, py::arg("from_system"), py::arg("picture"), py::arg("to_system"), py::arg("width") = py::none(),
        py::arg("height") = py::none(),
        "The picture laid on F's frame (its render.window, else its attractor's) carried onto G's attractor "
        "by the fractal homeomorphism phi_G o tau_F (3.3.5): RGBA (height, width, 4), alpha 0 off G; the "
        "TopsOptions given as keywords.");
  m.def("attractor_iou", [](const Ifs& ifs, const py::array& target, std::uint64_t seed, double threshold) {
    const PixelSet t = pixel_set_from_numpy(target, threshold);
    py::gil_scoped_release release;
    return attractor_iou(ifs, t, seed);
  }, py::arg("ifs"), py::arg("target"), py::arg("seed") = 0, py::arg("threshold") = 0.5,
        "Intersection over union of the attractor (chaos game) and the target laid on fit's window.");
}

}  // namespace ifsforge::python
