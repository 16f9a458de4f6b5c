// Mesh writers: PLY and OBJ through OpenMesh, binary glTF through tinygltf.
#include "ifsforge/io/mesh.h"

// OpenMesh's property containers trip GCC 12's -Wmaybe-uninitialized at instantiation.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "ifsforge/core/color.h"
#include "ifsforge/core/error.h"
#include "ifsforge/io/atomic_file.h"
#include "ifsforge/io/text_file.h"

namespace ifsforge {
namespace {

struct MeshTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3f;
  using Normal = OpenMesh::Vec3f;
  using Color = OpenMesh::Vec4f;
  using TexCoord2D = OpenMesh::Vec2f;
  VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Color |
                   OpenMesh::Attributes::TexCoord2D);
};
using OMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

std::string extension_of(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

void validate(const TriangleMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  if (n == 0 || mesh.triangles.empty()) throw InputError("the mesh is empty: nothing to write");
  if (n > 0xFFFFFFFFu) throw InputError("the mesh has more vertices than 32-bit indices address");
  auto check = [&](std::size_t size, const char* what) {
    if (size != 0 && size != n)
      throw InputError(std::string("the mesh has ") + std::to_string(size) + " " + what + " for " +
                       std::to_string(n) + " vertices");
  };
  check(mesh.normals.size(), "normals");
  check(mesh.colors.size(), "colours");
  check(mesh.uvs.size(), "uvs");
  for (const auto& t : mesh.triangles)
    for (std::uint32_t v : t)
      if (v >= n) throw InputError("a triangle refers to vertex " + std::to_string(v) + " of " + std::to_string(n));
  for (const auto& p : mesh.positions)
    for (float c : p)
      if (!std::isfinite(c)) throw InputError("the mesh has a vertex that is NaN or infinite");
}

void write_with_openmesh(const std::string& path, const std::string& ext, const TriangleMesh& mesh, Up up) {
  // OpenMesh's writers log "[OBJWriter] : write file" to stderr: noise in a command's output.
  omlog().disable();
  OMesh om;
  std::vector<OMesh::VertexHandle> handles;
  handles.reserve(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto p = oriented(mesh.positions[i], up);
    const auto v = om.add_vertex(OMesh::Point(p[0], p[1], p[2]));
    if (!mesh.normals.empty()) {
      const auto n = oriented(mesh.normals[i], up);
      om.set_normal(v, OMesh::Normal(n[0], n[1], n[2]));
    }
    if (!mesh.colors.empty()) {
      const auto& c = mesh.colors[i];
      om.set_color(v, OMesh::Color(c[0], c[1], c[2], c[3]));
    }
    if (!mesh.uvs.empty()) om.set_texcoord2D(v, OMesh::TexCoord2D(mesh.uvs[i][0], mesh.uvs[i][1]));
    handles.push_back(v);
  }
  std::size_t skipped = 0;
  for (const auto& t : mesh.triangles) {
    // OpenMesh refuses non-manifold faces; a writer must not silently drop them.
    if (!om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]).is_valid()) ++skipped;
  }
  if (skipped)
    throw InputError("cannot write '" + path + "': " + std::to_string(skipped) +
                     " triangles are not manifold (OpenMesh rejects them); write .glb instead");
  OpenMesh::IO::Options options;
  if (!mesh.normals.empty()) options += OpenMesh::IO::Options::VertexNormal;
  // OBJ has no standard vertex colour (OpenMesh's writer refuses it): colour goes to PLY and GLB.
  if (!mesh.colors.empty() && ext == "ply") options += OpenMesh::IO::Options::VertexColor;
  if (!mesh.uvs.empty()) options += OpenMesh::IO::Options::VertexTexCoord;
  if (ext == "ply") {
    options += OpenMesh::IO::Options::Binary;
    if (!mesh.colors.empty()) options += OpenMesh::IO::Options::ColorAlpha;
  }
  std::ostringstream out;
  if (!OpenMesh::IO::write_mesh(om, out, "." + ext, options, 9))
    throw FileError("cannot write '" + path + "': OpenMesh failed to encode the " + ext + " file");
  const std::string bytes = out.str();
  AtomicFile file(path);
  std::fwrite(bytes.data(), 1, bytes.size(), file.file());
  file.commit();
}

template <typename T>
int add_accessor(tinygltf::Model& model, const std::vector<T>& data, int component_type, int type,
                 int target, bool with_bounds) {
  tinygltf::Buffer& buffer = model.buffers[0];
  // Every view starts 4-byte aligned, as glTF requires.
  while (buffer.data.size() % 4) buffer.data.push_back(0);
  const std::size_t offset = buffer.data.size();
  const std::size_t bytes = data.size() * sizeof(T);
  buffer.data.resize(offset + bytes);
  std::memcpy(buffer.data.data() + offset, data.data(), bytes);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = offset;
  view.byteLength = bytes;
  view.target = target;
  model.bufferViews.push_back(view);
  tinygltf::Accessor accessor;
  accessor.bufferView = static_cast<int>(model.bufferViews.size() - 1);
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = type == TINYGLTF_TYPE_SCALAR ? data.size() * (sizeof(T) / 4) : data.size();
  if (with_bounds) {  // POSITION needs min and max
    std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (const auto& v : data)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], static_cast<double>(v[c]));
        hi[c] = std::max(hi[c], static_cast<double>(v[c]));
      }
    accessor.minValues.assign(lo.begin(), lo.end());
    accessor.maxValues.assign(hi.begin(), hi.end());
  }
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size() - 1);
}

/// The vectors in `up` axes (a copy only when they change).
const std::vector<std::array<float, 3>>& oriented_all(const std::vector<std::array<float, 3>>& in, Up up,
                                                      std::vector<std::array<float, 3>>& storage) {
  if (up == Up::z) return in;
  storage.resize(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) storage[i] = oriented(in[i], up);
  return storage;
}

void write_glb(const std::string& path, const TriangleMesh& mesh, const MeshWriteOptions& options, Up up) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "ifsforge";
  model.buffers.resize(1);
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  std::vector<std::array<float, 3>> storage;
  primitive.attributes["POSITION"] = add_accessor(model, oriented_all(mesh.positions, up, storage),
                                                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                                                  TINYGLTF_TARGET_ARRAY_BUFFER, true);
  if (!mesh.normals.empty())
    primitive.attributes["NORMAL"] = add_accessor(model, oriented_all(mesh.normals, up, storage),
                                                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                                                  TINYGLTF_TARGET_ARRAY_BUFFER, false);
  if (!mesh.colors.empty()) {
    // glTF's COLOR_0 is linear; alpha is not encoded.
    std::vector<std::array<float, 4>> linear(mesh.colors.size());
    for (std::size_t i = 0; i < linear.size(); ++i) {
      const auto& c = mesh.colors[i];
      linear[i] = {srgb_to_linear(c[0]), srgb_to_linear(c[1]), srgb_to_linear(c[2]), std::clamp(c[3], 0.0f, 1.0f)};
    }
    primitive.attributes["COLOR_0"] = add_accessor(model, linear, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                   TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER, false);
  }
  if (!mesh.uvs.empty())
    primitive.attributes["TEXCOORD_0"] = add_accessor(model, mesh.uvs, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                      TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER, false);
  primitive.indices = add_accessor(model, mesh.triangles, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                   TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, false);
  tinygltf::Material material;
  material.name = options.name;
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 0.8;
  material.doubleSided = true;
  if (!options.base_color_texture.empty()) {
    if (mesh.uvs.empty()) throw InputError("a base colour texture needs texture coordinates (uvs)");
    // The PNG's bytes go into the binary buffer as they are (image/png), no re-encoding.
    const std::string png = read_text_file(options.base_color_texture);
    tinygltf::Buffer& buffer = model.buffers[0];
    while (buffer.data.size() % 4) buffer.data.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer.data.size();
    view.byteLength = png.size();
    buffer.data.insert(buffer.data.end(), png.begin(), png.end());
    model.bufferViews.push_back(view);
    tinygltf::Image image;
    image.name = options.name + "_base_color";
    image.mimeType = "image/png";
    image.bufferView = static_cast<int>(model.bufferViews.size() - 1);
    model.images.push_back(image);
    tinygltf::Sampler sampler;
    sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    model.samplers.push_back(sampler);
    tinygltf::Texture texture;
    texture.source = 0;
    texture.sampler = 0;
    model.textures.push_back(texture);
    material.pbrMetallicRoughness.baseColorTexture.index = 0;
  }
  model.materials.push_back(material);
  primitive.material = 0;
  tinygltf::Mesh gmesh;
  gmesh.name = options.name;
  gmesh.primitives.push_back(primitive);
  model.meshes.push_back(gmesh);
  tinygltf::Node node;
  node.name = options.name;
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, out, false, true))
    throw FileError("cannot write '" + path + "': tinygltf failed to encode the glTF");
  const std::string bytes = out.str();
  AtomicFile file(path);
  std::fwrite(bytes.data(), 1, bytes.size(), file.file());
  file.commit();
}

}  // namespace

void write_mesh(const std::string& path, const TriangleMesh& mesh, const MeshWriteOptions& options) {
  const std::string ext = extension_of(path);
  if (ext != "ply" && ext != "obj" && ext != "glb")
    throw InputError("cannot write '" + path + "': mesh files end in .ply, .obj or .glb");
  check_writable(path);
  validate(mesh);
  const Up up = options.up.value_or(default_up(path));
  if (ext == "glb")
    write_glb(path, mesh, options, up);
  else
    write_with_openmesh(path, ext, mesh, up);
}

}  // namespace ifsforge
