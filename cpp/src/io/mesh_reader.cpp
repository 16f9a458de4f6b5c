// Reading user meshes through OpenMesh (the primitives of "mesh:PATH").
#include "ifsforge/io/mesh_reader.h"

// OpenMesh's property containers trip GCC 12's -Wmaybe-uninitialized at instantiation.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

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

/// The header lines of a PLY file, checked word by word: OpenMesh's PLY reader trusts its
/// header and crashes on a malformed one (found by fuzzing). Returns the declared elements.
double ply_header_elements(std::istream& in, const std::string& path) {
  static const std::set<std::string> kTypes = {"char",  "uchar",  "short",  "ushort", "int",     "uint",
                                               "float", "double", "int8",   "uint8",  "int16",   "uint16",
                                               "int32", "uint32", "float32", "float64"};
  double elements = 0;
  bool format = false;
  std::string line;
  for (int number = 2; number <= 1000 && std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "end_header") {
      if (format) return elements;
      break;
    }
    if (key == "comment" || key == "obj_info") continue;
    std::vector<std::string> w;
    for (std::string word; words >> word;) w.push_back(word);
    bool ok = false;
    if (key == "format") {
      ok = format = w.size() == 2 && (w[0] == "ascii" || w[0] == "binary_little_endian" ||
                                      w[0] == "binary_big_endian") && w[1] == "1.0";
    } else if (key == "element") {
      ok = w.size() == 2 && !w[1].empty() && w[1].size() <= 12 &&
           w[1].find_first_not_of("0123456789") == std::string::npos;
      if (ok) elements += std::stod(w[1]);
    } else if (key == "property") {
      ok = (w.size() == 2 && kTypes.count(w[0])) ||
           (w.size() == 4 && w[0] == "list" && kTypes.count(w[1]) && kTypes.count(w[2]));
    }
    if (!ok) throw InputError("mesh '" + path + "':" + std::to_string(number) + ": not a PLY header line: '" + line + "'");
  }
  throw InputError("mesh '" + path + "': the PLY header has no format line or no end_header in its first 1000 lines");
}

/// An OFF header: its keyword ([ST][C][N][4][n]OFF) alone on its line, then two non-negative
/// counts on the next line that is not a comment. OpenMesh reads a
/// count that does not parse (or is negative) as a huge size (found by fuzzing).
double off_header_elements(std::istream& in, const std::string& first, const std::string& path) {
  std::istringstream words(first);
  std::string keyword, rest;
  words >> keyword;
  const std::size_t off = keyword.rfind("OFF");
  const bool keyword_ok = off != std::string::npos && off + 3 == keyword.size() &&
                          keyword.substr(0, off).find_first_not_of("STCN4n") == std::string::npos;
  std::getline(words, rest);
  std::istringstream counts(rest);
  std::string v, f;
  if (!(counts >> v)) {
    std::string line;
    while (std::getline(in, line) && (line.empty() || line[0] == '#')) {
    }
    counts = std::istringstream(line);
    counts >> v;
  } else if (v == "BINARY") {
    throw InputError("mesh '" + path + "': binary OFF is not read (its counts cannot be checked first); "
                     "write the mesh as PLY or ASCII OFF");
  } else if (keyword_ok) {
    // OpenMesh skips the rest of the keyword's line and takes the next line for the counts: it
    // read a first vertex "3 508000000" as counts and reserved 6 GB (found by fuzzing).
    throw InputError("mesh '" + path + "': the OFF counts must be on the line after the keyword '" + keyword +
                     "' (the reader takes that line for them)");
  }
  counts >> f;
  auto count = [](const std::string& word) {
    return !word.empty() && word.size() <= 12 && word.find_first_not_of("0123456789") == std::string::npos;
  };
  if (!keyword_ok || !count(v) || !count(f))
    throw InputError("mesh '" + path + "': not an OFF header (a keyword such as OFF or COFF, then the vertex and "
                     "face counts)");
  const double vertices = std::stod(v), faces = std::stod(f);
  // Each face's corner count, which OpenMesh reserves before it reads the corners.
  std::string line;
  double seen_vertices = 0, seen_faces = 0;
  while (seen_faces < faces && std::getline(in, line)) {
    const std::size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    if (seen_vertices < vertices) {
      ++seen_vertices;
      continue;
    }
    std::istringstream corners(line);
    double n = -1;
    corners >> n;
    if (!(n >= 1 && n <= vertices))
      throw InputError("mesh '" + path + "': face " + std::to_string(static_cast<long long>(seen_faces)) +
                       " does not start with a corner count between 1 and the " +
                       std::to_string(static_cast<long long>(vertices)) + " vertices");
    ++seen_faces;
  }
  return vertices + faces;
}

/// Checks an OBJ file's faces: OpenMesh's OBJ reader asserts (aborts) on a face whose corner
/// has no vertex index, e.g. "f /1 2 3" (found by fuzzing), and drops out-of-range ones silently.
/// Every corner must be v, v/t, v//n or v/t/n with each index in 1..count (or -count..-1,
/// counted back from the last one read), and every face needs three corners.
void check_obj_faces(std::istream& in, const std::string& path) {
  double counts[3] = {0, 0, 0};  // v, vt, vn read so far
  auto index_ok = [](const std::string& word, double count) {
    const std::size_t digits = word[0] == '-' ? 1 : 0;
    if (word.size() <= digits || word.size() > 12 + digits ||
        word.find_first_not_of("0123456789", digits) != std::string::npos)
      return false;
    const double i = std::stod(word);
    return i != 0 && std::abs(i) <= count;
  };
  // Physical lines, not joined at a trailing '\': a corner that is a backslash is refused,
  // whichever way a reader treats continued lines.
  std::string line;
  for (long number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "v" || key == "vt" || key == "vn") {
      ++counts[key == "v" ? 0 : key == "vt" ? 1 : 2];
      continue;
    }
    if (key != "f") continue;
    int corners = 0;
    for (std::string corner; words >> corner; ++corners) {
      std::vector<std::string> part;
      std::istringstream slashes(corner + "/");
      for (std::string p; std::getline(slashes, p, '/');) part.push_back(p);
      const bool ok = part.size() <= 3 && index_ok(part[0], counts[0]) &&
                      (part.size() < 2 || (part[1].empty() ? part.size() == 3 : index_ok(part[1], counts[1]))) &&
                      (part.size() < 3 || index_ok(part[2], counts[2]));
      if (!ok)
        throw InputError("mesh '" + path + "':" + std::to_string(number) + ": face corner '" + corner +
                         "' is not v, v/t, v//n or v/t/n with indices among the " +
                         std::to_string(static_cast<long long>(counts[0])) + " vertices read so far");
    }
    if (corners < 3)
      throw InputError("mesh '" + path + "':" + std::to_string(number) + ": a face needs three corners");
  }
}

/// OpenMesh reserves what a PLY or OFF header declares before reading a vertex: a header
/// claiming more elements than the file has bytes is refused here, and the declared counts are
/// checked against the memory budget (~100 bytes a vertex or face once read).
void check_declared_counts(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(0, std::ios::end);
  const double bytes = static_cast<double>(in.tellg());
  in.seekg(0);
  std::string line;
  double elements = 0;
  std::getline(in, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  // OpenMesh picks its reader by the extension, in either case.
  auto named = [&path](const char* lower, const char* upper) {
    return path.size() >= 4 && (path.compare(path.size() - 4, 4, lower) == 0 || path.compare(path.size() - 4, 4, upper) == 0);
  };
  const bool ply_name = named(".ply", ".PLY");
  if (line == "ply") {
    elements = ply_header_elements(in, path);
  } else if (ply_name) {
    throw InputError("mesh '" + path + "': a PLY file starts with the line 'ply'");
  } else if (line.find("OFF") != std::string::npos && line.find("OFF") < 8) {
    elements = off_header_elements(in, line, path);
  } else if (named(".obj", ".OBJ")) {
    in.seekg(0);
    check_obj_faces(in, path);
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
