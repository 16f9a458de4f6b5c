// Instanced binary glTF. The JSON is streamed by hand rather than built as a tinygltf::Model:
// a model holds ~1 kB per node, which a million instances turn into gigabytes.
#include "ifsforge/io/gltf_instances.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

#include "ifsforge/core/color.h"
#include "ifsforge/core/error.h"
#include "ifsforge/io/atomic_file.h"
#include "ifsforge/geometry/axes.h"

namespace ifsforge {
namespace {

using Mat3 = std::array<std::array<double, 3>, 3>;

void json_number(std::string& out, double v) {
  char buffer[32];
  out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, std::isfinite(v) ? static_cast<float>(v) : 0.0f).ptr);
}

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      out += buffer;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

/// The unit quaternion (x, y, z, w) of a rotation matrix (Shepperd's method).
std::array<double, 4> quaternion(const Mat3& m) {
  const double trace = m[0][0] + m[1][1] + m[2][2];
  std::array<double, 4> q;
  if (trace > 0.0) {
    const double s = 2.0 * std::sqrt(1.0 + trace);
    q = {(m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s};
  } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]);
    q = {0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s};
  } else if (m[1][1] > m[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]);
    q = {(m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]);
    q = {(m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s, (m[1][0] - m[0][1]) / s};
  }
  const double l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& v : q) v /= l;
  return q;
}

struct Binary {
  std::string bytes;
  std::string views;  // JSON of the bufferViews
  int view_count = 0;
  int add(const void* data, std::size_t size, int target) {
    while (bytes.size() % 4) bytes += '\0';
    const std::size_t offset = bytes.size();
    bytes.append(static_cast<const char*>(data), size);
    if (view_count) views += ',';
    views += "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) + ",\"byteLength\":" + std::to_string(size) +
             ",\"target\":" + std::to_string(target) + "}";
    return view_count++;
  }
};

}  // namespace

void write_gltf_instances(const std::string& path, const InstanceList& list, const GltfInstanceOptions& options) {
  const Up up = options.up;
  // The columns of C: where our unit axes land in the file's axes.
  const std::array<float, 3> axes[3] = {oriented(1, 0, 0, up), oriented(0, 1, 0, up), oriented(0, 0, 1, up)};
  if (options.color_levels < 0 || options.color_levels == 1 || options.color_levels > 256)
    throw InputError("color levels must be 0 (no per-color meshes) or 2..256");
  check_writable(path);

  // Geometry: one set of accessors per primitive.
  Binary bin;
  std::string accessors;
  int accessor_count = 0;
  struct Geometry { int position, normal, indices; };
  std::vector<Geometry> geometry;
  for (const Primitive& p : list.primitives) {
    const TriangleMesh mesh = primitive_mesh(p, options.segments);
    std::vector<float> positions, normals;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const auto& q = mesh.positions[v];
      const auto g = oriented(q, up);
      for (int c = 0; c < 3; ++c) {
        positions.push_back(g[c]);
        lo[c] = std::min(lo[c], g[c]);
        hi[c] = std::max(hi[c], g[c]);
      }
      const auto& n = mesh.normals.size() == mesh.positions.size() ? mesh.normals[v] : std::array<float, 3>{0, 0, 1};
      const auto gn = oriented(n, up);
      normals.insert(normals.end(), gn.begin(), gn.end());
    }
    std::vector<std::uint32_t> indices;
    for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
    const std::size_t count = mesh.positions.size();
    auto accessor = [&](int view, std::size_t n, int component, const char* type, const std::string& bounds) {
      if (accessor_count) accessors += ',';
      accessors += "{\"bufferView\":" + std::to_string(view) + ",\"componentType\":" + std::to_string(component) +
                   ",\"count\":" + std::to_string(n) + ",\"type\":\"" + type + "\"" + bounds + "}";
      return accessor_count++;
    };
    std::string bounds = ",\"min\":[";
    for (int c = 0; c < 3; ++c) {
      if (c) bounds += ',';
      json_number(bounds, lo[c]);
    }
    bounds += "],\"max\":[";
    for (int c = 0; c < 3; ++c) {
      if (c) bounds += ',';
      json_number(bounds, hi[c]);
    }
    bounds += "]";
    Geometry g;
    g.position = accessor(bin.add(positions.data(), positions.size() * 4, 34962), count, 5126, "VEC3", bounds);
    g.normal = accessor(bin.add(normals.data(), normals.size() * 4, 34962), count, 5126, "VEC3", "");
    g.indices = accessor(bin.add(indices.data(), indices.size() * 4, 34963), indices.size(), 5125, "SCALAR", "");
    geometry.push_back(g);
  }

  // Colour classes in order of first use: one material each, one mesh per (primitive, class).
  const int levels = options.color_levels;
  using ClassKey = std::tuple<int, int, int, int>;
  std::map<ClassKey, int> classes;
  std::vector<ClassKey> class_order;
  std::map<std::pair<int, int>, int> meshes;  // (primitive, class) -> mesh index
  std::vector<std::pair<int, int>> mesh_order;
  std::vector<int> node_mesh(list.size(), -1);
  auto quantise = [&](float c) { return static_cast<int>(std::lround(std::clamp(c, 0.0f, 1.0f) * (levels - 1))); };
  std::size_t visible = 0;
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (!(list.scales[i] > 0.0f) || !std::isfinite(list.scales[i])) continue;
    ++visible;
    ClassKey key{0, 0, 0, 0};
    if (levels > 0) {
      const auto& c = list.colors[i];
      key = {quantise(c[0]), quantise(c[1]), quantise(c[2]), quantise(c[3])};
    }
    auto found = classes.find(key);
    if (found == classes.end()) {
      found = classes.emplace(key, static_cast<int>(class_order.size())).first;
      class_order.push_back(key);
    }
    const std::pair<int, int> mesh_key{list.primitive[i], found->second};
    auto m = meshes.find(mesh_key);
    if (m == meshes.end()) {
      m = meshes.emplace(mesh_key, static_cast<int>(mesh_order.size())).first;
      mesh_order.push_back(mesh_key);
    }
    node_mesh[i] = m->second;
  }
  if (visible == 0) throw InputError("no instance has a positive scale: nothing to draw");

  std::string json = "{\"asset\":{\"version\":\"2.0\",\"generator\":\"ifsforge vector recursive rendering\"},";
  json += "\"scene\":0,\"scenes\":[{\"name\":" + json_string(options.name.empty() ? list.name : options.name) + ",\"nodes\":[0]}],";
  json += "\"materials\":[";
  for (std::size_t k = 0; k < class_order.size(); ++k) {
    const auto& key = class_order[k];
    double rgba[4] = {0.8, 0.8, 0.8, 1.0};
    if (levels > 0) {
      const int q[4] = {std::get<0>(key), std::get<1>(key), std::get<2>(key), std::get<3>(key)};
      for (int c = 0; c < 4; ++c) rgba[c] = static_cast<double>(q[c]) / (levels - 1);
      for (int c = 0; c < 3; ++c) rgba[c] = srgb_to_linear(rgba[c]);
    }
    if (k) json += ',';
    json += "{\"name\":\"ifs_color_" + std::to_string(k) + "\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[";
    for (int c = 0; c < 4; ++c) {
      if (c) json += ',';
      json_number(json, rgba[c]);
    }
    json += "],\"metallicFactor\":0,\"roughnessFactor\":0.6},\"doubleSided\":true";
    if (rgba[3] < 0.9995) json += ",\"alphaMode\":\"BLEND\"";
    json += '}';
  }
  json += "],\"meshes\":[";
  for (std::size_t k = 0; k < mesh_order.size(); ++k) {
    const auto [prim, cls] = mesh_order[k];
    const Geometry& g = geometry[prim];
    if (k) json += ',';
    json += "{\"name\":" + json_string(list.primitives[prim].name() + "_" + std::to_string(cls)) +
            ",\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(g.position) +
            ",\"NORMAL\":" + std::to_string(g.normal) + "},\"indices\":" + std::to_string(g.indices) +
            ",\"material\":" + std::to_string(cls) + "}]}";
  }
  json += "],\"nodes\":[{\"name\":" + json_string(options.name.empty() ? list.name : options.name) + ",\"children\":[";
  for (std::size_t i = 0, child = 1; i < list.size(); ++i) {
    if (node_mesh[i] < 0) continue;
    if (child > 1) json += ',';
    json += std::to_string(child++);
  }
  json += "]}";
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (node_mesh[i] < 0) continue;
    const auto& p = list.positions[i];
    const auto& f = list.frames[i];
    // The frame R has columns e1, e2, e3 and the stored meshes are C v (C: the axis rotation),
    // so the node rotation is R' = C R C^T, whose column j is sum_k C[j][k] (C e_k).
    const std::array<float, 3> ce[3] = {oriented(f[0], f[1], f[2], up), oriented(f[3], f[4], f[5], up),
                                        oriented(f[6], f[7], f[8], up)};
    Mat3 r;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        r[i][j] = 0.0;
        for (int k = 0; k < 3; ++k) r[i][j] += double(axes[k][j]) * ce[k][i];
      }
    const auto q = quaternion(r);
    const auto t = oriented(p[0], p[1], p[2], up);
    json += ",{\"name\":" + json_string(list.addresses.to_string(i)) + ",\"mesh\":" + std::to_string(node_mesh[i]) +
            ",\"translation\":[";
    for (int c = 0; c < 3; ++c) {
      if (c) json += ',';
      json_number(json, t[c]);
    }
    json += "],\"rotation\":[";
    for (int c = 0; c < 4; ++c) {
      if (c) json += ',';
      json_number(json, q[c]);
    }
    json += "],\"scale\":[";
    for (int c = 0; c < 3; ++c) {
      if (c) json += ',';
      json_number(json, list.scales[i]);
    }
    json += ']';
    if (options.extras) {
      json += ",\"extras\":{\"address\":" + json_string(list.addresses.to_string(i)) + ",\"color\":[";
      for (int c = 0; c < 4; ++c) {
        if (c) json += ',';
        json_number(json, list.colors[i][c]);
      }
      json += "],\"primitive\":" + std::to_string(list.primitive[i]) + "}";
    }
    json += '}';
  }
  json += "],\"accessors\":[" + accessors + "],\"bufferViews\":[" + bin.views + "],";
  while (bin.bytes.size() % 4) bin.bytes += '\0';
  json += "\"buffers\":[{\"byteLength\":" + std::to_string(bin.bytes.size()) + "}]}";
  while (json.size() % 4) json += ' ';

  // GLB container: header, JSON chunk, BIN chunk (little-endian).
  const std::uint32_t total = static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.bytes.size());
  if (12.0 + 8.0 + json.size() + 8.0 + bin.bytes.size() > 4294967295.0)
    throw InputError("the glTF file would exceed 4 GB; use fewer instances");
  auto u32 = [](std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
  std::string header;
  u32(header, 0x46546C67u);  // "glTF"
  u32(header, 2);
  u32(header, total);
  u32(header, static_cast<std::uint32_t>(json.size()));
  u32(header, 0x4E4F534Au);  // "JSON"
  AtomicFile file(path);
  write_bytes(file.file(), header.data(), header.size(), path);
  write_bytes(file.file(), json.data(), json.size(), path);
  std::string chunk;
  u32(chunk, static_cast<std::uint32_t>(bin.bytes.size()));
  u32(chunk, 0x004E4942u);  // "BIN\0"
  write_bytes(file.file(), chunk.data(), chunk.size(), path);
  write_bytes(file.file(), bin.bytes.data(), bin.bytes.size(), path);
  file.commit();
}

}  // namespace ifsforge
