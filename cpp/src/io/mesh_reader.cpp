// Reading user meshes through OpenMesh (the primitives of "mesh:PATH").
#include "ifsforge/io/mesh_reader.h"

// OpenMesh's property containers trip GCC 12's -Wmaybe-uninitialized at instantiation.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <unistd.h>

#include <cmath>

#include "ifsforge/core/error.h"

namespace ifsforge {
namespace {

struct ReadTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3f;
  using Normal = OpenMesh::Vec3f;
  VertexAttributes(OpenMesh::Attributes::Normal);
  FaceAttributes(OpenMesh::Attributes::Normal);
};
using ReadMesh = OpenMesh::PolyMesh_ArrayKernelT<ReadTraits>;

}  // namespace

TriangleMesh read_mesh(const std::string& path) {
  if (access(path.c_str(), R_OK) != 0) throw FileError("cannot read mesh '" + path + "': no such readable file");
  ReadMesh mesh;
  OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexNormal;
  if (!OpenMesh::IO::read_mesh(mesh, path, options))
    throw FileError("cannot read mesh '" + path + "': not a PLY, OBJ, OFF or STL file OpenMesh can read");
  if (!options.check(OpenMesh::IO::Options::VertexNormal)) {
    mesh.update_face_normals();
    mesh.update_vertex_normals();
  }
  TriangleMesh out;
  out.positions.reserve(mesh.n_vertices());
  for (const auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    const auto n = mesh.normal(v);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InputError("mesh '" + path + "' has a vertex that is NaN or infinite");
    out.positions.push_back({p[0], p[1], p[2]});
    out.normals.push_back({n[0], n[1], n[2]});
  }
  // Polygons become fans around their first vertex (OpenMesh keeps faces as read).
  for (const auto f : mesh.faces()) {
    std::vector<std::uint32_t> ring;
    for (const auto v : mesh.fv_range(f)) ring.push_back(static_cast<std::uint32_t>(v.idx()));
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) out.triangles.push_back({ring[0], ring[k], ring[k + 1]});
  }
  if (out.triangles.empty()) throw InputError("mesh '" + path + "' has no faces");
  return out;
}

}  // namespace ifsforge
