// Mesh writers: PLY and OBJ of our own (mesh_files.cpp), binary glTF through tinygltf.
#include "ifsforge/io/mesh.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <ostream>
#include <streambuf>

#include "ifsforge/core/color.h"
#include "ifsforge/core/error.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/io/atomic_file.h"
#include "ifsforge/io/text_file.h"
#include "mesh_files.h"

namespace ifsforge {
namespace {

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
  check(mesh.colors.size(), "colors");
  check(mesh.uvs.size(), "uvs");
  for (const auto& t : mesh.triangles)
    for (std::uint32_t v : t)
      if (v >= n) throw InputError("a triangle refers to vertex " + std::to_string(v) + " of " + std::to_string(n));
  for (const auto& p : mesh.positions)
    for (float c : p)
      if (!std::isfinite(c)) throw InputError("the mesh has a vertex that is NaN or infinite");
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
  resize_large(storage, in.size());
  for (std::size_t i = 0; i < in.size(); ++i) storage[i] = oriented(in[i], up);
  return storage;
}

/// tinygltf's output straight into the file, in 16 MB pieces with a progress check between them
/// (the buffer is one write of up to gigabytes). A cancel or a failed write makes the stream fail
/// (tinygltf then stops writing); the writer throws after tinygltf returns.
class FileBuffer : public std::streambuf {
 public:
  FileBuffer(std::FILE* file, const ProgressCallback& progress, double total)
      : file_(file), progress_(progress), total_(total) {}
  bool cancelled = false, failed = false;

 protected:
  std::streamsize xsputn(const char* data, std::streamsize size) override {
    constexpr std::streamsize kPiece = 16 << 20;
    for (std::streamsize done = 0; done < size; done += kPiece) {
      if (cancelled || failed) return 0;
      const std::size_t piece = static_cast<std::size_t>(std::min(kPiece, size - done));
      failed = std::fwrite(data + done, 1, piece, file_) != piece;
      written_ += static_cast<double>(piece);
      if (progress_ && !progress_(std::min(1.0, written_ / total_))) cancelled = true;
    }
    return size;
  }
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
  }

 private:
  std::FILE* file_;
  const ProgressCallback& progress_;
  double total_, written_ = 0.0;
};

void write_glb(const std::string& path, const TriangleMesh& mesh, const MeshWriteOptions& options, Up up) {
  // The arrays are copied into the model (first half of the progress), then written.
  auto check = [&](double fraction) {
    if (options.progress && !options.progress(fraction)) throw Cancelled();
  };
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "ifsforge";
  model.buffers.resize(1);
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  std::vector<std::array<float, 3>> storage;
  // The binary buffer at its final size at once (views of floats and indices need no padding;
  // a texture's PNG grows it): huge pages, faulted in on every core, and never copied to grow.
  reserve_large(model.buffers[0].data, (mesh.positions.size() + mesh.normals.size()) * 12 + mesh.colors.size() * 16 +
                                           mesh.uvs.size() * 8 + mesh.triangles.size() * 12);
  check(0.0);
  primitive.attributes["POSITION"] = add_accessor(model, oriented_all(mesh.positions, up, storage),
                                                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                                                  TINYGLTF_TARGET_ARRAY_BUFFER, true);
  check(0.1);
  if (!mesh.normals.empty())
    primitive.attributes["NORMAL"] = add_accessor(model, oriented_all(mesh.normals, up, storage),
                                                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                                                  TINYGLTF_TARGET_ARRAY_BUFFER, false);
  check(0.2);
  if (!mesh.colors.empty()) {
    // glTF's COLOR_0 is linear; alpha is not encoded.
    std::vector<std::array<float, 4>> linear;
    resize_large(linear, mesh.colors.size());
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
  check(0.3);
  primitive.indices = add_accessor(model, mesh.triangles, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                   TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, false);
  tinygltf::Material material;
  material.name = options.name;
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 0.8;
  material.doubleSided = true;
  if (!options.base_color_texture.empty()) {
    if (mesh.uvs.empty()) throw InputError("a base color texture needs texture coordinates (uvs)");
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
  check(0.5);
  AtomicFile file(path);
  const ProgressCallback writing = progress_range(options.progress, 0.5, 1.0);
  FileBuffer buffer(file.file(), writing, static_cast<double>(model.buffers[0].data.size()) + 1.0);
  std::ostream out(&buffer);
  tinygltf::TinyGLTF writer;
  const bool encoded = writer.WriteGltfSceneToStream(&model, out, false, true);
  if (buffer.cancelled) throw Cancelled();
  if (buffer.failed) throw FileError("cannot write '" + path + "': " + std::strerror(errno));
  if (!encoded || !out) throw FileError("cannot write '" + path + "': tinygltf failed to encode the glTF");
  check(1.0);
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
  if (ext == "glb") {
    write_glb(path, mesh, options, up);
    return;
  }
  // PLY stores indices as int.
  if (ext == "ply" && mesh.positions.size() > 0x7FFFFFFFu)
    throw InputError("cannot write '" + path + "': PLY indices are 31-bit, the mesh has more vertices; write .glb instead");
  AtomicFile file(path);
  if (ext == "ply")
    detail::write_ply(file.file(), path, mesh, up, options.progress);
  else
    detail::write_obj(file.file(), path, mesh, up, options.progress);
  file.commit();
}

}  // namespace ifsforge
