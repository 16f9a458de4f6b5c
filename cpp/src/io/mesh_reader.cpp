// Reading user meshes through OpenMesh (the primitives of "mesh:PATH").
#include "ifsforge/io/mesh_reader.h"

// OpenMesh's property containers trip GCC 12's -Wmaybe-uninitialized at instantiation.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"

namespace ifsforge {
namespace {

struct ReadTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3f;
  using Normal = OpenMesh::Vec3f;
  VertexAttributes(OpenMesh::Attributes::Normal);
  FaceAttributes(OpenMesh::Attributes::Normal);
};
using ReadMesh = OpenMesh::PolyMesh_ArrayKernelT<ReadTraits>;

/// OpenMesh reserves what a PLY or OFF header declares before reading a vertex: a header
/// claiming more elements than the file has bytes is refused here, and the declared counts are
/// checked against the memory budget (~100 bytes a vertex or face once read).
void check_declared_counts(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(0, std::ios::end);
  const double bytes = static_cast<double>(in.tellg());
  in.seekg(0);
  std::string line, word;
  double elements = 0;
  std::getline(in, line);
  if (line.rfind("ply", 0) == 0) {
    for (int n = 0; n < 1000 && std::getline(in, line) && line.rfind("end_header", 0) != 0; ++n) {
      std::istringstream words(line);
      std::string kind;
      double count = 0;
      if (words >> word >> kind >> count && word == "element") elements += count;
    }
  } else if (line.rfind("OFF", 0) == 0 || line.rfind("COFF", 0) == 0 || line.rfind("NOFF", 0) == 0) {
    std::istringstream rest(line.substr(line.find("OFF") + 3));
    double v = 0, f = 0;
    if (!(rest >> v >> f)) {
      while (std::getline(in, line) && (line.empty() || line[0] == '#')) {
      }
      std::istringstream counts(line);
      counts >> v >> f;
    }
    elements = v + f;
  }
  if (elements > bytes)
    throw InputError("mesh '" + path + "': the header declares " + std::to_string(static_cast<long long>(elements)) +
                     " elements, more than the file's " + std::to_string(static_cast<long long>(bytes)) + " bytes hold");
  check_memory(100.0 * elements, "reading mesh '" + path + "'");
}

}  // namespace

TriangleMesh read_mesh(const std::string& path) {
  if (access(path.c_str(), R_OK) != 0) throw FileError("cannot read mesh '" + path + "': no such readable file");
  check_declared_counts(path);
  ReadMesh mesh;
  OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexNormal;
  bool read = false;
  try {
    read = OpenMesh::IO::read_mesh(mesh, path, options);
  } catch (const std::bad_alloc&) {
    throw MemoryBudgetError("reading mesh '" + path + "' ran out of memory");
  }
  if (!read)
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
