// Triangle meshes: write PLY / OBJ / GLB from numpy arrays.
#include "bindings.h"

#include <cstring>
#include "ifsforge/core/error.h"
#include "ifsforge/io/mesh.h"
#include "ifsforge/io/mesh_edges.h"

namespace ifsforge::python {
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
  m.def("write_mesh",
        [](const std::string& path, py::array positions, py::array triangles, std::optional<py::array> normals,
           std::optional<py::array> colors, std::optional<py::array> uvs, const std::string& texture,
           const std::string& name, bool compute) {
          TriangleMesh mesh;
          mesh.positions = rows<float, 3>(positions, "positions");
          mesh.triangles = rows<std::uint32_t, 3>(triangles, "triangles");
          mesh.normals = rows<float, 3>(normals, "normals");
          mesh.colors = rows<float, 4>(colors, "colors");
          mesh.uvs = rows<float, 2>(uvs, "uvs");
          py::gil_scoped_release release;
          if (compute && mesh.normals.empty()) compute_normals(mesh);
          write_mesh(path, mesh, MeshWriteOptions{texture, name});
        },
        py::arg("path"), py::arg("positions"), py::arg("triangles"), py::arg("normals") = py::none(),
        py::arg("colors") = py::none(), py::arg("uvs") = py::none(), py::arg("texture") = "",
        py::arg("name") = "ifsforge", py::arg("compute_normals") = true,
        "Write a triangle mesh as .ply, .obj or .glb (atomically). colors are RGBA in [0, 1]; texture is a "
        "PNG embedded as the glTF base colour (needs uvs).");
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
