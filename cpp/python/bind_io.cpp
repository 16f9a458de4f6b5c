// Every reader and writer: ifsforge/1 JSON, Fractint .ifs, PNG, meshes (PLY/OBJ/GLB, OpenMesh
// readers), POV-Ray scenes, SVG, glTF instances and DF3 volumes. OpenVDB is in bind_io_vdb.cpp, a
// module of its own (ifsforge._vdb) loaded on first use: libopenvdb is slow to load.
#include "bindings.h"

#include <cstring>

#include "ifsforge/core/error.h"
#include "ifsforge/io/atomic_file.h"
#include "ifsforge/io/df3.h"
#include "ifsforge/io/fractint.h"
#include "ifsforge/io/system_file.h"
#include "ifsforge/io/gltf_instances.h"
#include "ifsforge/io/pov_scene.h"
#include "ifsforge/io/ifs_json.h"
#include "ifsforge/io/mesh.h"
#include "ifsforge/geometry/mesh_edges.h"
#include "ifsforge/io/mesh_reader.h"
#include "ifsforge/io/png.h"
#include "ifsforge/io/pov_instances.h"
#include "ifsforge/render/tone_map.h"
#include "ifsforge/io/povray.h"
#include "ifsforge/io/svg.h"

namespace ifsforge::python {

Image image_from_numpy(const py::array& array) {
  if (array.ndim() != 2 && array.ndim() != 3) throw InputError("an image array must be (h, w) or (h, w, c)");
  const int h = static_cast<int>(array.shape(0)), w = static_cast<int>(array.shape(1));
  const int c = array.ndim() == 3 ? static_cast<int>(array.shape(2)) : 1;
  if (c < 1 || c > 4) throw InputError("an image has 1 to 4 channels");
  double scale = 1.0;
  if (py::isinstance<py::array_t<std::uint8_t>>(array)) scale = 1.0 / 255.0;
  if (py::isinstance<py::array_t<std::uint16_t>>(array)) scale = 1.0 / 65535.0;
  auto values = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!values) throw InputError("an image array must hold numbers");
  Image image(w, h, c);
  const float* src = values.data();
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<float>(src[i] * scale);
  return image;
}

py::array_t<float> image_to_numpy(const Image& image) {
  if (image.channels == 1) return to_numpy(image.pixels, {image.height, image.width});
  return to_numpy(image.pixels, {image.height, image.width, image.channels});
}

std::optional<Up> up_argument(const py::object& up) {
  if (up.is_none()) return std::nullopt;
  if (py::isinstance<Up>(up)) return up.cast<Up>();
  if (py::isinstance<py::str>(up)) return parse_name<Up>(up.cast<std::string>());
  throw InputError("up is 'y', 'z' or None, not " + py::repr(up).cast<std::string>());
}

namespace {

template <typename T, std::size_t N>
std::vector<std::array<T, N>> rows(const std::optional<py::array>& array, const char* what) {
  std::vector<std::array<T, N>> out;
  if (!array) return out;
  auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(*array);
  if (!a || a.ndim() != 2 || a.shape(1) != static_cast<py::ssize_t>(N))
    throw InputError(std::string(what) + " must be an array of shape (n, " + std::to_string(N) + ")");
  out.resize(a.shape(0));
  std::memcpy(out.data(), a.data(), out.size() * sizeof(out[0]));
  return out;
}

}  // namespace

void bind_io(py::module_& m) {
  add_choices<Up>(m, "up");
  add_choices<PovQuality>(m, "quality");
  m.def("write_bytes", [](const std::string& path, const py::object& data) {
    if (!py::isinstance<py::bytes>(data) && !py::isinstance<py::str>(data))
      throw InputError("write_bytes: " + path + ": the data must be bytes or str");
    const std::string bytes = data.cast<std::string>();  // str: UTF-8
    py::gil_scoped_release release;
    AtomicFile file(path);
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file.file()) != bytes.size())
      throw FileError("cannot write '" + path + "'");
    file.commit();
  }, py::arg("path"), py::arg("data"),
     "Write bytes (or str, as UTF-8) to path atomically (AtomicFile): a failure leaves no partial file.");
  m.attr("FORMAT_VERSION") = kFormatVersion;
  m.def("load", &load_system, py::arg("spec"),
        "A system from 'file.json', 'file.ifs' (first entry) or 'file.ifs:entry'.");
  m.def("read_json", &read_ifs_json, py::arg("path"));
  m.def("parse_json", &parse_ifs_json, py::arg("text"), py::arg("source") = "<json>");
  m.def("to_json", &to_ifs_json, py::arg("ifs"));
  m.def("write_json", &write_ifs_json, py::arg("path"), py::arg("ifs"), "Atomic write of the canonical JSON.");
  m.def("read_fractint", &read_fractint, py::arg("path"), "Every entry of a Fractint .ifs file.");
  m.def("parse_fractint", &parse_fractint, py::arg("text"), py::arg("source") = "<ifs>");
  // The Raster overload comes first: a raster written this way never imports numpy (the
  // array overload's type check would), which keeps a small `ifsforge render` fast.
  m.def("write_png", [](const std::string& path, const Raster& raster, int bit_depth, const py::object& mode,
                        const py::object& gamma, const py::object& invert) {
    py::dict given;
    add_option(given, "mode", mode);
    add_option(given, "gamma", gamma);
    add_option(given, "invert", invert);
    const ToneOptions options = options_from<ToneOptions>("write_png", given);
    py::gil_scoped_release release;
    write_png(path, tone_map(raster, options), bit_depth);
  }, py::arg("path"), py::arg("raster"), py::arg("bit_depth") = 8, py::kw_only(), py::arg("mode") = py::none(),
     py::arg("gamma") = py::none(), py::arg("invert") = py::none(),
     "Write a raster's picture (Raster.to_image with the ToneOptions given as keywords) as an 8- or 16-bit PNG, "
     "atomically.");
  m.def("write_png", [](const std::string& path, const py::array& array, int bit_depth) {
    Image image = image_from_numpy(array);
    py::gil_scoped_release release;
    write_png(path, image, bit_depth);
  }, py::arg("path"), py::arg("image"), py::arg("bit_depth") = 8,
     "Write (h, w[, c]) floats in [0, 1] (or uint8/uint16) as an 8- or 16-bit PNG, atomically.");
  m.def("read_png", [](const std::string& path) { return image_to_numpy(read_png(path)); }, py::arg("path"),
        "A PNG as float32 in [0, 1], shape (h, w) or (h, w, c).");

  py::enum_<Up>(m, "Up", "A mesh file's up axis. ifsforge's own axes are z up (x east, y north); a y-up file "
                         "holds (x, z, -y): glTF and OBJ expect y, PLY z.")
      .value("y", Up::y)
      .value("z", Up::z);
  m.def("default_up", &default_up, py::arg("path"),
        "The up axis the reader of `path` expects by its extension: .glb/.gltf/.obj y, else (.ply) z.");
  options_class<MeshWriteOptions>(m, "MeshWriteOptions", "The settings of write_mesh() (keywords of the same names).")
      .def_readwrite("base_color_texture", &MeshWriteOptions::base_color_texture,
                     "glTF: a PNG embedded as the material's base color (needs uvs)")
      .def_readwrite("name", &MeshWriteOptions::name, "glTF: the mesh and node name")
      .def_property("up", [](const MeshWriteOptions& o) { return o.up; },
                    [](MeshWriteOptions& o, const py::object& up) { o.up = up_argument(up); },
                    "the file's up axis ('y', 'z'; None: the format's, see default_up)");
  m.def("write_mesh",
        [](const std::string& path, py::array positions, py::array triangles, std::optional<py::array> normals,
           std::optional<py::array> colors, std::optional<py::array> uvs, bool compute, const py::object& progress,
           const py::kwargs& kwargs) {
          TriangleMesh mesh;
          mesh.positions = rows<float, 3>(positions, "positions");
          mesh.triangles = rows<std::uint32_t, 3>(triangles, "triangles");
          mesh.normals = rows<float, 3>(normals, "normals");
          mesh.colors = rows<float, 4>(colors, "colors");
          mesh.uvs = rows<float, 2>(uvs, "uvs");
          MeshWriteOptions options = options_from<MeshWriteOptions>("write_mesh", kwargs);
          // Always a callback: Ctrl-C stops the writing even when the caller passed none.
          const ProgressCallback report = wrap_progress(progress);
          py::gil_scoped_release release;
          const bool computing = compute && mesh.normals.empty();
          if (computing) compute_normals(mesh, progress_range(report, 0.0, 0.2));
          options.progress = progress_range(report, computing ? 0.2 : 0.0, 1.0);
          write_mesh(path, mesh, options);
        },
        py::arg("path"), py::arg("positions"), py::arg("triangles"), py::arg("normals") = py::none(),
        py::arg("colors") = py::none(), py::arg("uvs") = py::none(), py::arg("compute_normals") = true,
        py::arg("progress") = py::none(),
        "Write a triangle mesh given in ifsforge's z-up axes as .ply, .obj or .glb (atomically): the "
        "MeshWriteOptions given as keywords (up: the file's axis). colors are display RGBA in [0, 1] (the .glb "
        "stores them linear). progress(fraction) returning False cancels (no file is left).");
  m.def("mesh_edges",
        [](py::array faces, std::size_t vertex_count) {
          auto a = py::array_t<std::uint32_t, py::array::c_style | py::array::forcecast>::ensure(faces);
          if (!a || a.ndim() != 2 || a.shape(1) < 3)
            throw InputError("faces must be an array of shape (n, k) with k >= 3 corners per face");
          const std::vector<std::uint32_t> corners(a.data(), a.data() + a.size());
          const int k = static_cast<int>(a.shape(1));
          MeshEdges e;
          {
            py::gil_scoped_release release;
            e = mesh_edges(corners, k, vertex_count);
          }
          return py::make_tuple(rows_array(std::move(e.edges)), vector_array(std::move(e.corner_edges)));
        },
        py::arg("faces"), py::arg("vertex_count"),
        "(edges (E, 2) uint32, corner_edges (n*k,) uint32) of faces (n, k): each undirected edge once, sorted, and "
        "the edge of every corner j of a face (from its vertex j to j+1) -- what a mesh editor stores (Blender's "
        "edges and loops).");
  m.def("read_mesh", [](const std::string& path) { return mesh_dict(read_mesh(path)); }, py::arg("path"),
        "A PLY/OBJ/OFF/STL mesh (OpenMesh), triangulated: {'positions', 'normals', 'triangles'}.");

  options_class<PovSceneOptions>(m, "PovSceneOptions",
                                  "The settings of write_pov_scene() (keywords of the same names).")
      .def_readwrite("title", &PovSceneOptions::title, "first comment line and IFS_Title; default: the list's name")
      .def_readwrite("width", &PovSceneOptions::width, "the image the camera is framed for")
      .def_readwrite("height", &PovSceneOptions::height)
      .def_property("view", [](const PovSceneOptions& o) { return std::array<double, 2>{o.view.yaw, o.view.pitch}; },
                    [](PovSceneOptions& o, std::array<double, 2> v) { o.view.yaw = v[0], o.view.pitch = v[1]; },
                    "(yaw, pitch) in degrees, as `render --view` (2D lists: from above)")
      .def_property("orthographic", [](const PovSceneOptions& o) { return o.view.orthographic; },
                    [](PovSceneOptions& o, bool v) { o.view.orthographic = v; })
      .def_property("fov", [](const PovSceneOptions& o) { return o.view.fov; },
                    [](PovSceneOptions& o, double v) { o.view.fov = v; }, "perspective: horizontal field of view, degrees")
      .def_property("margin", [](const PovSceneOptions& o) { return o.view.margin; },
                    [](PovSceneOptions& o, double v) { o.view.margin = v; }, "free border, fraction of the image")
      .def_property("background", [](const PovSceneOptions& o) { return o.environment.background; },
                    [](PovSceneOptions& o, std::array<float, 3> v) { o.environment.background = v; },
                    "RGB behind the scene when there is no sky")
      .def_property("quality", [](const PovSceneOptions& o) { return std::string(name_of(o.environment.quality)); },
                    [](PovSceneOptions& o, const std::string& q) { o.environment.quality = parse_name<PovQuality>(q); },
                    "draft (no shadows), normal or high (soft shadows, radiosity)")
      .def_readwrite("bounded_by", &PovSceneOptions::bounded_by, "a manual bound (slow to trace in POV-Ray 3.7)")
      .def_readwrite("threads", &PovSceneOptions::threads, "formatting threads; the bytes never depend on it")
      .def_property("progress", [](const PovSceneOptions&) { return py::none(); },
                    [](PovSceneOptions& o, const py::object& f) { o.progress = wrap_progress(f); },
                    "progress(fraction) returning False cancels (write-only)");
  m.def("write_pov_scene",
        [](const std::string& path, const InstanceList& list, std::optional<bool> floor, std::optional<bool> sky,
           const py::kwargs& kwargs) {
          PovSceneOptions o = options_from<PovSceneOptions>("write_pov_scene", kwargs);
          o.environment.floor = floor.value_or(list.spatial_dims == 3);
          o.environment.sky = sky.value_or(list.spatial_dims == 3);
          py::gil_scoped_release release;
          write_pov_scene(path, list, o);
        },
        py::arg("path"), py::arg("instances"), py::kw_only(), py::arg("floor") = py::none(),
        py::arg("sky") = py::none(),
        "A POV-Ray 3.7 scene (+ ifsforge.inc beside it): one union of the instances, camera and lights framed "
        "for width x height from the instances' bounds: the PovSceneOptions given as keywords. floor and sky "
        "(None: on for 3D lists).");
  options_class<PovRenderOptions>(m, "PovRenderOptions", "The settings of render_povray() (keywords of the same names).")
      .def_readwrite("width", &PovRenderOptions::width)
      .def_readwrite("height", &PovRenderOptions::height)
      .def_readwrite("antialias", &PovRenderOptions::antialias, "POV-Ray's +A threshold (0: off)")
      .def_readwrite("threads", &PovRenderOptions::threads, "0: every core")
      .def_property("progress", [](const PovRenderOptions&) { return py::none(); },
                    [](PovRenderOptions& o, const py::object& f) { o.progress = wrap_progress(f); },
                    "progress(fraction) returning False cancels (write-only)");
  m.def("render_povray",
        [](const std::string& scene, const std::string& image, const py::object& width, const py::object& height,
           const py::kwargs& kwargs) {
          py::dict given(kwargs);
          add_option(given, "width", width);
          add_option(given, "height", height);
          const PovRenderOptions o = options_from<PovRenderOptions>("render_povray", given);
          py::gil_scoped_release release;
          render_povray(scene, image, o);
        },
        py::arg("scene"), py::arg("image"), py::arg("width") = py::none(), py::arg("height") = py::none(),
        "Render a scene with the real POV-Ray 3.7 (headless) into a PNG, atomically.");
  m.def("povray_include", &povray_include, "the text of ifsforge.inc");
  m.def("write_povray_include", &write_povray_include, py::arg("folder"));
  m.def("pov_string", &pov_string, py::arg("text"), "a POV-Ray string literal holding text (ASCII, escaped)");
  m.def("pov_comment", &pov_comment, py::arg("text"), "text made safe inside a // comment (one ASCII line)");
  m.def("pov_identifier", &pov_identifier, py::arg("kind"), py::arg("name"),
        "the identifier IFS_<kind>_<name> (name reduced to ASCII letters, digits and '_')");
  m.def("pov_name", &pov_name, py::arg("name"), "the name part of pov_identifier");
  m.def("ascii_text", &ascii_text, py::arg("text"), py::arg("unknown") = '?',
        "text in printable ASCII: accents dropped, other characters as `unknown`");
  m.def("pov_reserved_words", [] {
    std::vector<std::string> words;
    for (const auto w : pov_reserved_words()) words.emplace_back(w);
    return words;
  }, "POV-Ray 3.7's reserved words, sorted");

  options_class<SvgOptions>(m, "SvgOptions", "The settings of write_svg() (keywords of the same names).")
      .def_readwrite("width", &SvgOptions::width, "pixels; the height follows the instances' aspect ratio")
      .def_readwrite("margin", &SvgOptions::margin, "free border, fraction of the larger side")
      .def_readwrite("background", &SvgOptions::background, "RGB; None: transparent")
      .def_readwrite("title", &SvgOptions::title, "default: the list's name");
  m.def("write_svg",
        [](const std::string& path, const InstanceList& list, const py::kwargs& kwargs) {
          const SvgOptions o = options_from<SvgOptions>("write_svg", kwargs);
          py::gil_scoped_release release;
          write_svg(path, list, o);
        },
        py::arg("path"), py::arg("instances"), "SVG of a 2D instance list, one element per instance.");
  options_class<GltfInstanceOptions>(m, "GltfInstanceOptions",
                                     "The settings of write_gltf_instances() (keywords of the same names).")
      .def_readwrite("segments", &GltfInstanceOptions::segments, "tessellation of the curved primitives")
      .def_readwrite("color_levels", &GltfInstanceOptions::color_levels, "levels per channel of the color classes")
      .def_readwrite("extras", &GltfInstanceOptions::extras, "node extras: address, color, primitive")
      .def_readwrite("name", &GltfInstanceOptions::name, "the root node; default: the list's name")
      .def_property("up", [](const GltfInstanceOptions& o) { return o.up; },
                    [](GltfInstanceOptions& o, const py::object& up) { o.up = up_argument(up).value_or(o.up); },
                    "the file's up axis: 'y' (glTF's) or 'z'");
  m.def("write_gltf_instances",
        [](const std::string& path, const InstanceList& list, const py::kwargs& kwargs) {
          const GltfInstanceOptions o = options_from<GltfInstanceOptions>("write_gltf_instances", kwargs);
          py::gil_scoped_release release;
          write_gltf_instances(path, list, o);
        },
        py::arg("path"), py::arg("instances"),
        "Binary glTF: each primitive's mesh stored once, one node per instance (Blender: linked duplicates); "
        "materials hold the display colors as linear baseColorFactor; up: 'y' (None: glTF's) or 'z'.");

  m.def("write_df3",
        [](const std::string& path, const Volume& volume, int bits, const std::string& content, bool border) {
          const Df3Content what = parse_name<Df3Content>(content);
          py::gil_scoped_release release;
          write_df3(path, volume, bits, what, border);
        },
        py::arg("path"), py::arg("volume"), py::arg("bits") = 8, py::arg("content") = "density", py::arg("border") = false,
        "Write one grid of the volume as a POV-Ray .df3 (atomically): big-endian uint16 sizes x, y, z, then "
        "8/16/32-bit big-endian voxels, x fastest, scaled to the full range. content: 'density' (density / max "
        "density) or 'red', 'green', 'blue' (a channel of the linear color, srgb_to_linear of the display one). border: one empty voxel around "
        "the grid (POV-Ray's interpolation wraps round at the unit cube's faces).");
}

}  // namespace ifsforge::python
