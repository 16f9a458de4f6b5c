// Triangle meshes: write PLY / OBJ / GLB from numpy arrays; the up-axis convention and the
// colour rule shared by every writer.
#include "bindings.h"

#include <cstring>
#include "ifsforge/core/colour.h"
#include "ifsforge/core/error.h"
#include "ifsforge/io/mesh.h"
#include "ifsforge/geometry/mesh_edges.h"

namespace ifsforge::python {

std::optional<Up> up_argument(const py::object& up) {
  if (up.is_none()) return std::nullopt;
  if (py::isinstance<Up>(up)) return up.cast<Up>();
  if (py::isinstance<py::str>(up)) return up_from_string(up.cast<std::string>());
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

void bind_mesh(py::module_& m) {
  py::enum_<Up>(m, "Up", "A mesh file's up axis. ifsforge's own axes are z up (x east, y north); a y-up file "
                         "holds (x, z, -y): glTF and OBJ expect y, PLY z.")
      .value("y", Up::y)
      .value("z", Up::z);
  m.def("default_up", &default_up, py::arg("path"),
        "The up axis the reader of `path` expects by its extension: .glb/.gltf/.obj y, else (.ply) z.");
  m.def("srgb_to_linear", py::vectorize([](double c) { return srgb_to_linear<double>(c); }), py::arg("c"),
        "Display (sRGB-encoded) colour values in [0, 1] to linear light (IEC 61966-2-1), clamped first: what "
        "glTF COLOR_0/baseColorFactor, the .vdb colour grid and Blender colour attributes hold.");
  m.def("linear_to_srgb", py::vectorize([](double c) { return linear_to_srgb(c); }), py::arg("c"),
        "The inverse of srgb_to_linear on [0, 1].");
  m.def("write_mesh",
        [](const std::string& path, py::array positions, py::array triangles, std::optional<py::array> normals,
           std::optional<py::array> colors, std::optional<py::array> uvs, const std::string& texture,
           const std::string& name, bool compute, const py::object& up) {
          TriangleMesh mesh;
          mesh.positions = rows<float, 3>(positions, "positions");
          mesh.triangles = rows<std::uint32_t, 3>(triangles, "triangles");
          mesh.normals = rows<float, 3>(normals, "normals");
          mesh.colors = rows<float, 4>(colors, "colors");
          mesh.uvs = rows<float, 2>(uvs, "uvs");
          MeshWriteOptions options;
          options.base_color_texture = texture;
          options.name = name;
          const std::optional<Up> file_up = up_argument(up);
          py::gil_scoped_release release;
          if (compute && mesh.normals.empty()) compute_normals(mesh);
          options.up = file_up;
          write_mesh(path, mesh, options);
        },
        py::arg("path"), py::arg("positions"), py::arg("triangles"), py::arg("normals") = py::none(),
        py::arg("colors") = py::none(), py::arg("uvs") = py::none(), py::arg("texture") = "",
        py::arg("name") = "ifsforge", py::arg("compute_normals") = true, py::arg("up") = py::none(),
        "Write a triangle mesh given in ifsforge's z-up axes as .ply, .obj or .glb (atomically), turned to "
        "`up` ('y', 'z'; None: the format's, see default_up). colors are display RGBA in [0, 1] (the .glb "
        "stores them linear); texture is a PNG embedded as the glTF base colour (needs uvs).");
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
          py::array_t<std::uint32_t> edges({static_cast<py::ssize_t>(e.edges.size()), py::ssize_t(2)});
          py::array_t<std::uint32_t> corner_edges(static_cast<py::ssize_t>(e.corner_edges.size()));
          std::memcpy(edges.mutable_data(), e.edges.data(), e.edges.size() * sizeof(e.edges[0]));
          std::memcpy(corner_edges.mutable_data(), e.corner_edges.data(),
                      e.corner_edges.size() * sizeof(std::uint32_t));
          return py::make_tuple(edges, corner_edges);
        },
        py::arg("faces"), py::arg("vertex_count"),
        "(edges (E, 2) uint32, corner_edges (n*k,) uint32) of faces (n, k): each undirected edge once, sorted, and "
        "the edge of every corner j of a face (from its vertex j to j+1) -- what a mesh editor stores (Blender's "
        "edges and loops).");
}

const Binding registered(25, &bind_mesh);

}  // namespace
}  // namespace ifsforge::python
