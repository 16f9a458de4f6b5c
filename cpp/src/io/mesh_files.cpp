#include "mesh_files.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <vector>

#include "ifsforge/core/parallel.h"
#include "ifsforge/io/atomic_file.h"

namespace ifsforge::detail {
namespace {

// Elements formatted by one job; a batch of jobs is formatted in parallel, then written in
// order before the next batch, so the text in memory stays near 64 x 16 K lines.
constexpr std::size_t kPerJob = 1 << 14;
constexpr std::size_t kJobsPerBatch = 64;

/// Writes count elements: format(first, last, out) appends elements [first, last) to out.
/// `from`, `to`: this section's share of `progress`.
template <typename Format>
void write_section(std::FILE* file, const std::string& path, std::size_t count, const Format& format,
                   const ProgressCallback& progress, double from, double to) {
  const std::size_t jobs = (count + kPerJob - 1) / kPerJob;
  std::vector<std::string> chunks(std::min(jobs, kJobsPerBatch));
  for (std::size_t batch = 0; batch < jobs; batch += kJobsPerBatch) {
    const std::size_t n = std::min(kJobsPerBatch, jobs - batch);
    const double a = from + (to - from) * batch / jobs, b = from + (to - from) * (batch + n) / jobs;
    parallel_jobs(n, 0, [&](std::size_t job, int) {
      const std::size_t first = (batch + job) * kPerJob;
      chunks[job].clear();
      format(first, std::min(count, first + kPerJob), chunks[job]);
    }, progress_range(progress, a, b));
    for (std::size_t job = 0; job < n; ++job) write_bytes(file, chunks[job].data(), chunks[job].size(), path);
  }
}

template <typename T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

std::uint8_t byte(float c) { return static_cast<std::uint8_t>(std::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f); }

/// Appends " x" for each value (shortest text that reads back as the same float).
template <typename T>
void numbers(std::string& out, const T* values, int count) {
  char buffer[32];
  for (int i = 0; i < count; ++i) {
    buffer[0] = ' ';
    const auto end = std::to_chars(buffer + 1, buffer + sizeof buffer, values[i]).ptr;
    out.append(buffer, end);
  }
}

}  // namespace

void write_ply(std::FILE* file, const std::string& path, const TriangleMesh& mesh, Up up,
               const ProgressCallback& progress) {
  const bool normals = !mesh.normals.empty(), colors = !mesh.colors.empty(), uvs = !mesh.uvs.empty();
  std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(mesh.positions.size()) +
                       "\nproperty float x\nproperty float y\nproperty float z\n";
  if (normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (colors) header += "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n";
  if (uvs) header += "property float u\nproperty float v\n";
  header += "element face " + std::to_string(mesh.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  write_bytes(file, header.data(), header.size(), path);
  const std::size_t vertices = mesh.positions.size(), faces = mesh.triangles.size();
  const double split = static_cast<double>(vertices) / static_cast<double>(vertices + faces);
  write_section(file, path, vertices, [&](std::size_t first, std::size_t last, std::string& out) {
    out.reserve((last - first) * 36);
    for (std::size_t v = first; v < last; ++v) {
      put(out, oriented(mesh.positions[v], up));
      if (normals) put(out, oriented(mesh.normals[v], up));
      if (colors)
        for (float c : mesh.colors[v]) put(out, byte(c));
      if (uvs) put(out, mesh.uvs[v]);
    }
  }, progress, 0.0, split);
  write_section(file, path, faces, [&](std::size_t first, std::size_t last, std::string& out) {
    out.reserve((last - first) * 13);
    for (std::size_t f = first; f < last; ++f) {
      put(out, std::uint8_t{3});
      put(out, mesh.triangles[f]);  // the indices are below 2^31 (validated): as int they are the same bytes
    }
  }, progress, split, 1.0);
}

void write_obj(std::FILE* file, const std::string& path, const TriangleMesh& mesh, Up up,
               const ProgressCallback& progress) {
  const bool normals = !mesh.normals.empty(), uvs = !mesh.uvs.empty();
  const std::string header = "# " + std::to_string(mesh.positions.size()) + " vertices, " +
                             std::to_string(mesh.triangles.size()) + " faces\n";
  write_bytes(file, header.data(), header.size(), path);
  const std::size_t vertices = mesh.positions.size(), faces = mesh.triangles.size();
  const double split = static_cast<double>(vertices) / static_cast<double>(vertices + faces);
  write_section(file, path, vertices, [&](std::size_t first, std::size_t last, std::string& out) {
    out.reserve((last - first) * (normals ? 64 : 32));
    for (std::size_t v = first; v < last; ++v) {
      out += 'v';
      numbers(out, oriented(mesh.positions[v], up).data(), 3);
      if (uvs) {
        out += "\nvt";
        numbers(out, mesh.uvs[v].data(), 2);
      }
      if (normals) {
        out += "\nvn";
        numbers(out, oriented(mesh.normals[v], up).data(), 3);
      }
      out += '\n';
    }
  }, progress, 0.0, split);
  // Every vertex has its own texture coordinate and normal, at its own index.
  const char* const format = uvs && normals ? "/#/#" : uvs ? "/#" : normals ? "//#" : "";
  write_section(file, path, faces, [&](std::size_t first, std::size_t last, std::string& out) {
    out.reserve((last - first) * 40);
    char buffer[16];
    for (std::size_t f = first; f < last; ++f) {
      out += 'f';
      for (std::uint32_t index : mesh.triangles[f]) {
        const auto end = std::to_chars(buffer, buffer + sizeof buffer, std::uint64_t{index} + 1).ptr;
        out += ' ';
        out.append(buffer, end);
        for (const char* c = format; *c; ++c) {
          if (*c == '#') out.append(buffer, end);
          else out += *c;
        }
      }
      out += '\n';
    }
  }, progress, split, 1.0);
}

}  // namespace ifsforge::detail
