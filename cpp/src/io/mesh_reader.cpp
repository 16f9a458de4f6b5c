// Reading user meshes through OpenMesh (the primitives of "mesh:PATH").
#include "ifsforge/io/mesh_reader.h"

// OpenMesh's property containers trip GCC 12's -Wmaybe-uninitialized at instantiation.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <mutex>
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

/// One element of a PLY header: its name, count and properties (name, whether a list).
struct PlyElement {
  std::string name;
  double count = 0;
  std::vector<std::pair<std::string, bool>> properties;
};

struct PlyHeader {
  bool ascii = false;
  std::vector<PlyElement> elements;
  double total = 0;  ///< elements of every kind
};

/// The header lines of a PLY file, checked word by word: OpenMesh's PLY reader trusts its
/// header and crashes on a malformed one (found by fuzzing).
PlyHeader ply_header(std::istream& in, const std::string& path) {
  static const std::set<std::string> kTypes = {"char",  "uchar",  "short",  "ushort", "int",     "uint",
                                               "float", "double", "int8",   "uint8",  "int16",   "uint16",
                                               "int32", "uint32", "float32", "float64"};
  PlyHeader header;
  bool format = false;
  std::string line;
  for (int number = 2; number <= 1000 && std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "end_header") {
      if (format) return header;
      break;
    }
    if (key == "comment" || key == "obj_info") continue;
    std::vector<std::string> w;
    for (std::string word; words >> word;) w.push_back(word);
    bool ok = false;
    if (key == "format") {
      ok = format = w.size() == 2 && (w[0] == "ascii" || w[0] == "binary_little_endian" ||
                                      w[0] == "binary_big_endian") && w[1] == "1.0";
      header.ascii = ok && w[0] == "ascii";
    } else if (key == "element") {
      ok = w.size() == 2 && !w[1].empty() && w[1].size() <= 12 &&
           w[1].find_first_not_of("0123456789") == std::string::npos;
      if (ok) {
        header.elements.push_back({w[0], std::stod(w[1]), {}});
        header.total += header.elements.back().count;
      }
    } else if (key == "property") {
      ok = !header.elements.empty() && ((w.size() == 2 && kTypes.count(w[0])) ||
                                        (w.size() == 4 && w[0] == "list" && kTypes.count(w[1]) && kTypes.count(w[2])));
      if (ok) header.elements.back().properties.push_back({w.back(), w.size() == 4});
    }
    if (!ok) throw InputError("mesh '" + path + "':" + std::to_string(number) + ": not a PLY header line: '" + line + "'");
  }
  throw InputError("mesh '" + path + "': the PLY header has no format line or no end_header in its first 1000 lines");
}

std::string number_text(double n) { return std::to_string(static_cast<long long>(n)); }

/// InputError: vertex `index` (0-based, as the file counts them) is not finite.
[[noreturn]] void non_finite_vertex(const std::string& path, double index) {
  throw InputError("mesh '" + path + "': vertex " + number_text(index) + " has a non-finite coordinate");
}

/// Reads a coordinate or index word as a number; NaN when it is none.
double number_of(const std::string& word) {
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  return end && *end == 0 && !word.empty() ? v : NAN;
}

/// Checks face `face`'s corner `word` against the `vertices` of the file (`base`: the first index).
void check_corner(const std::string& path, double face, const std::string& word, double vertices, double base) {
  const double i = number_of(word);
  if (std::isnan(i) || i != std::floor(i))
    throw InputError("mesh '" + path + "': face " + number_text(face) + " has a vertex index '" + word +
                     "' that is not a whole number");
  if (i < base || i >= vertices + base)
    throw InputError("mesh '" + path + "': face " + number_text(face) + " refers to vertex " + word +
                     " but the file has " + number_text(vertices) + " vertices");
}

/// An ASCII PLY's data, line by line after the header: every vertex finite, every face's
/// indices among the vertices (OpenMesh drops such faces and prints to stderr).
void check_ply_data(std::istream& in, const PlyHeader& header, const std::string& path) {
  double vertices = 0;
  for (const PlyElement& e : header.elements)
    if (e.name == "vertex") vertices += e.count;
  std::string line;
  for (const PlyElement& e : header.elements) {
    const bool vertex = e.name == "vertex", face = e.name == "face";
    for (double i = 0; i < e.count; ++i) {
      if (!std::getline(in, line)) return;  // short files are OpenMesh's to refuse
      if (!vertex && !face) continue;
      std::istringstream words(line);
      std::string word;
      for (const auto& [name, list] : e.properties) {
        if (!list) {
          if (!(words >> word)) return;
          if (vertex && (name == "x" || name == "y" || name == "z") && !std::isfinite(number_of(word)))
            non_finite_vertex(path, i);
          continue;
        }
        if (!(words >> word)) return;
        const double n = number_of(word);
        for (double k = 0; k < n && words >> word; ++k)
          if (face && (name == "vertex_indices" || name == "vertex_index")) check_corner(path, i, word, vertices, 0);
      }
    }
  }
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
    std::istringstream words(line.substr(start));
    std::string word;
    if (seen_vertices < vertices) {
      for (int c = 0; c < 3 && words >> word; ++c)
        if (!std::isfinite(number_of(word))) non_finite_vertex(path, seen_vertices);
      ++seen_vertices;
      continue;
    }
    words >> word;
    const double n = number_of(word);
    if (!(n >= 1 && n <= vertices))
      throw InputError("mesh '" + path + "': face " + number_text(seen_faces) +
                       " does not start with a corner count between 1 and the " + number_text(vertices) + " vertices");
    for (double k = 0; k < n && words >> word; ++k) check_corner(path, seen_faces, word, vertices, 0);
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
  double faces = 0;
  for (long number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "v") {
      std::string word;
      for (int c = 0; c < 3 && words >> word; ++c)
        if (!std::isfinite(number_of(word))) non_finite_vertex(path, counts[0]);
    }
    if (key == "v" || key == "vt" || key == "vn") {
      ++counts[key == "v" ? 0 : key == "vt" ? 1 : 2];
      continue;
    }
    if (key != "f") continue;
    ++faces;
    int corners = 0;
    for (std::string corner; words >> corner; ++corners) {
      std::vector<std::string> part;
      std::istringstream slashes(corner + "/");
      for (std::string p; std::getline(slashes, p, '/');) part.push_back(p);
      const bool ok = part.size() <= 3 && index_ok(part[0], counts[0]) &&
                      (part.size() < 2 || (part[1].empty() ? part.size() == 3 : index_ok(part[1], counts[1]))) &&
                      (part.size() < 3 || index_ok(part[2], counts[2]));
      const double v = number_of(part[0]);
      if (!ok && v == std::floor(v) && v != 0 && std::abs(v) > counts[0])
        throw InputError("mesh '" + path + "':" + std::to_string(number) + ": face " + number_text(faces - 1) +
                         " refers to vertex " + part[0] + " but the file has " + number_text(counts[0]) +
                         " vertices before it");
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
    const PlyHeader header = ply_header(in, path);
    elements = header.total;
    if (header.ascii) check_ply_data(in, header, path);
  } else if (ply_name) {
    throw InputError("mesh '" + path + "': a PLY file starts with the line 'ply'");
  } else if (line.find("OFF") != std::string::npos && line.find("OFF") < 8) {
    elements = off_header_elements(in, line, path);
  } else if (named(".obj", ".OBJ")) {
    in.seekg(0);
    check_obj_faces(in, path);
  } else if (named(".stl", ".STL") && line.compare(0, 5, "solid") == 0) {
    // ASCII STL: OpenMesh's parser takes "nan" for a number it cannot read. Its vertices are
    // the facets' corners, counted in the file's order.
    double corner = 0;
    while (std::getline(in, line)) {
      std::istringstream words(line);
      std::string key, word;
      if (!(words >> key) || key != "vertex") continue;
      for (int c = 0; c < 3; ++c)
        if (!(words >> word) || !std::isfinite(number_of(word))) non_finite_vertex(path, corner);
      ++corner;
    }
  }
  if (elements > bytes)
    throw InputError("mesh '" + path + "': the header declares " + std::to_string(static_cast<long long>(elements)) +
                     " elements, more than the file's " + std::to_string(static_cast<long long>(bytes)) + " bytes hold");
  check_memory(100.0 * elements, "reading mesh '" + path + "'");
}

/// OpenMesh's log, output and error streams gathered while it reads (they go to stderr raw
/// otherwise): its first line explains a refusal. One read at a time holds them.
class CapturedLog {
 public:
  CapturedLog() : lock_(mutex()) {
    for (std::size_t k = 0; k < streams().size(); ++k) {
      OpenMesh::mostream* s = streams()[k];
      had_cerr_[k] = s->disconnect(std::cerr);
      had_cout_[k] = s->disconnect(std::cout);
      s->connect(text_);
    }
  }
  ~CapturedLog() {
    for (std::size_t k = 0; k < streams().size(); ++k) {
      OpenMesh::mostream* s = streams()[k];
      s->flush();
      s->disconnect(text_);
      if (had_cerr_[k]) s->connect(std::cerr);
      if (had_cout_[k]) s->connect(std::cout);
    }
  }
  CapturedLog(const CapturedLog&) = delete;
  CapturedLog& operator=(const CapturedLog&) = delete;

  /// The first non-empty line written, "" when none.
  std::string first_line() {
    for (OpenMesh::mostream* s : streams()) s->flush();
    std::istringstream lines(text_.str());
    for (std::string line; std::getline(lines, line);)
      if (line.find_first_not_of(" \t\r") != std::string::npos) return line;
    return "";
  }

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static std::array<OpenMesh::mostream*, 3> streams() { return {&omerr(), &omlog(), &omout()}; }
  std::lock_guard<std::mutex> lock_;
  std::ostringstream text_;
  std::array<bool, 3> had_cerr_{}, had_cout_{};
};

}  // namespace

TriangleMesh read_mesh(const std::string& path) {
  if (access(path.c_str(), R_OK) != 0) throw FileError("cannot read mesh '" + path + "': no such readable file");
  check_declared_counts(path);
  ReadMesh mesh;
  OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexNormal;
  bool read = false;
  std::string said;  // OpenMesh's first line about the file
  {
    CapturedLog log;
    try {
      read = OpenMesh::IO::read_mesh(mesh, path, options);
    } catch (const std::bad_alloc&) {
      throw MemoryBudgetError("reading mesh '" + path + "' ran out of memory");
    }
    said = log.first_line();
  }
  const std::string reason = said.empty() ? "" : " (the reader said: " + said + ")";
  if (!read)
    throw FileError("cannot read mesh '" + path + "': not a PLY, OBJ, OFF or STL file OpenMesh can read" + reason);
  if (!options.check(OpenMesh::IO::Options::VertexNormal)) {
    mesh.update_face_normals();
    mesh.update_vertex_normals();
  }
  TriangleMesh out;
  out.positions.reserve(mesh.n_vertices());
  for (const auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    const auto n = mesh.normal(v);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) non_finite_vertex(path, v.idx());
    out.positions.push_back({p[0], p[1], p[2]});
    out.normals.push_back({n[0], n[1], n[2]});
  }
  // Polygons become fans around their first vertex (OpenMesh keeps faces as read).
  for (const auto f : mesh.faces()) {
    std::vector<std::uint32_t> ring;
    for (const auto v : mesh.fv_range(f)) ring.push_back(static_cast<std::uint32_t>(v.idx()));
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) out.triangles.push_back({ring[0], ring[k], ring[k + 1]});
  }
  if (out.triangles.empty())
    throw InputError("mesh '" + path + "' has no faces" + (said.empty() ? " (it holds " + std::to_string(mesh.n_vertices()) +
                     " vertices and no polygon of three or more corners)" : reason));
  return out;
}

}  // namespace ifsforge
