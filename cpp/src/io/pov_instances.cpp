#include "ifsforge/io/pov_instances.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/io/atomic_file.h"

namespace ifsforge {
namespace {

/// One instance as one line of the union; returns the end of the text (at most 400 bytes).
char* format_instance(char* out, const InstanceList& list, std::size_t i, const std::string& identifier) {
  const auto& p = list.positions[i];
  const float d = list.scales[i];
  const Primitive& primitive = list.primitives[list.primitive[i]];
  auto put = [&](const char* text) {
    while (*text) *out++ = *text++;
  };
  if (primitive.shape == Shape::Sphere) {
    put("sphere{");
    out = pov_vector(out, p[0], p[1], p[2]);
    *out++ = ',';
    out = pov_number(out, d);
  } else {
    put("object{");
    put(identifier.c_str());
    put(" matrix<");
    const auto& f = list.frames[i];
    for (int k = 0; k < 9; ++k) {
      out = pov_number(out, d * f[k]);
      *out++ = ',';
    }
    out = pov_number(out, p[0]);
    *out++ = ',';
    out = pov_number(out, p[1]);
    *out++ = ',';
    out = pov_number(out, p[2]);
    *out++ = '>';
  }
  const auto& c = list.colors[i];
  const bool transparent = c[3] < 0.9995f;
  put(transparent ? " pigment{srgbt<" : " pigment{srgb<");
  for (int k = 0; k < 3; ++k) {
    out = pov_unit(out, c[k]);
    *out++ = ',';
  }
  if (transparent) {
    out = pov_unit(out, 1.0f - c[3]);
    *out++ = ',';
  }
  out[-1] = '>';
  put("}}\n");
  return out;
}

std::string mesh2(const std::string& identifier, const TriangleMesh& mesh) {
  std::string s = "#declare " + identifier + " = mesh2 {\n  vertex_vectors { " + std::to_string(mesh.positions.size());
  char buffer[64];
  for (const auto& p : mesh.positions) s += ",\n    " + std::string(buffer, pov_vector(buffer, p[0], p[1], p[2]));
  s += "\n  }\n";
  if (mesh.normals.size() == mesh.positions.size()) {
    s += "  normal_vectors { " + std::to_string(mesh.normals.size());
    for (const auto& n : mesh.normals) s += ",\n    " + std::string(buffer, pov_vector(buffer, n[0], n[1], n[2]));
    s += "\n  }\n";
  }
  s += "  face_indices { " + std::to_string(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    s += ",\n    <" + std::to_string(t[0]) + "," + std::to_string(t[1]) + "," + std::to_string(t[2]) + ">";
  s += "\n  }\n}\n";
  return s;
}

}  // namespace

std::string pov_primitive_identifier(const Primitive& primitive, PovNames& names) {
  switch (primitive.shape) {
    case Shape::Line: return "IFS_Line";
    case Shape::Circle: return primitive.outline ? "IFS_Circle_Outline" : "IFS_Circle";
    case Shape::Triangle: return primitive.outline ? "IFS_Triangle_Outline" : "IFS_Triangle";
    case Shape::Square: return primitive.outline ? "IFS_Square_Outline" : "IFS_Square";
    case Shape::Sphere: return "IFS_Sphere";
    case Shape::Box: return "IFS_Box";
    case Shape::Cone: return "IFS_Cone";
    case Shape::Cylinder: return "IFS_Cylinder";
    case Shape::Torus: return "IFS_Torus";
    case Shape::Mesh: return names.take("Mesh", std::filesystem::path(primitive.mesh_path).stem().string());
  }
  return "IFS_Sphere";
}

PovFraming frame_instances(const InstanceList& list, const PovSceneOptions& options) {
  PovView view = options.view;
  if (list.spatial_dims == 2) {
    view.yaw = 0.0;
    view.pitch = 90.0;
  }
  std::vector<double> radius;
  for (const auto& p : list.primitives) radius.push_back(p.bounding_radius());
  std::vector<PovBall> balls;
  balls.reserve(list.size());
  for (std::size_t i = 0; i < list.size(); ++i)
    if (list.scales[i] > 0.0f && std::isfinite(list.scales[i])) {
      const auto& p = list.positions[i];
      balls.push_back({{p[0], p[1], p[2]}, list.scales[i] * radius[list.primitive[i]]});
    }
  if (balls.empty()) throw InputError("no instance has a positive scale: nothing to draw");
  return frame_balls(balls, view, options.width, options.height);
}

void write_pov_scene(const std::string& path, const InstanceList& list, const PovSceneOptions& options) {
  check_writable(path);
  std::array<double, 3> lo, hi;
  list.bounds(lo, hi);
  const PovFraming framing = frame_instances(list, options);
  PovNames scene_names;
  std::vector<std::string> identifiers;
  for (const Primitive& primitive : list.primitives)
    identifiers.push_back(pov_primitive_identifier(primitive, scene_names));

  std::size_t visible = 0;
  for (float s : list.scales) visible += s > 0.0f && std::isfinite(s);
  std::string names;
  for (const auto& p : list.primitives) names += (names.empty() ? "" : ", ") + p.name();
  const std::string title = options.title.empty() ? "IFS instances: " + list.name : options.title;
  const std::string about = std::to_string(visible) + " instances of " + names + " (vector recursive rendering, depth " +
                            std::to_string(list.addresses.depth) + ")";

  std::string head = pov_preamble(title, about, framing, options.environment, options.width, options.height);
  char buffer[64];
  head += "#declare IFS_Bounds_Min = " + std::string(buffer, pov_vector(buffer, lo[0], lo[1], lo[2])) + ";\n";
  head += "#declare IFS_Bounds_Max = " + std::string(buffer, pov_vector(buffer, hi[0], hi[1], hi[2])) + ";\n";
  for (std::size_t p = 0; p < list.primitives.size(); ++p)
    if (list.primitives[p].shape == Shape::Mesh) head += mesh2(identifiers[p], *list.primitives[p].mesh);
  head += "#default { finish { IFS_Finish } }\nunion {\n";

  write_povray_include(folder_of(path));
  AtomicFile file(path);
  write_bytes(file.file(), head.data(), head.size(), path);
  // Chunks are formatted in parallel a batch at a time and written in order: the bytes do not
  // depend on the thread count and memory stays bounded.
  constexpr std::size_t kChunk = 8192, kMaxLine = 400;
  const std::size_t n = list.size(), chunks = (n + kChunk - 1) / kChunk;
  const int threads = resolve_threads(options.threads);
  const std::size_t batch = static_cast<std::size_t>(threads) * 4;
  std::vector<std::string> text(batch);
  for (std::size_t first = 0; first < chunks; first += batch) {
    const std::size_t count = std::min(batch, chunks - first);
    ProgressCallback progress;
    if (options.progress)
      progress = [&](double f) { return options.progress((first + f * count) / static_cast<double>(chunks)); };
    parallel_jobs(count, threads, [&](std::size_t job, int) {
      const std::size_t begin = (first + job) * kChunk, end = std::min(n, begin + kChunk);
      std::string& out = text[job];
      out.resize((end - begin) * kMaxLine);
      char* cursor = out.data();
      for (std::size_t i = begin; i < end; ++i)
        if (list.scales[i] > 0.0f && std::isfinite(list.scales[i]))
          cursor = format_instance(cursor, list, i, identifiers[list.primitive[i]]);
      out.resize(static_cast<std::size_t>(cursor - out.data()));
    }, progress);
    for (std::size_t job = 0; job < count; ++job) write_bytes(file.file(), text[job].data(), text[job].size(), path);
  }
  std::string tail;
  if (options.bounded_by) tail += "bounded_by { box { IFS_Bounds_Min, IFS_Bounds_Max } }\n";
  tail += "}\n";
  write_bytes(file.file(), tail.data(), tail.size(), path);
  file.commit();
}

}  // namespace ifsforge
