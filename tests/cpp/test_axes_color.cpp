// The one up-axis convention and the one colour rule of the file writers: what each file holds,
// read back with the file's own reader (tinygltf, OpenMesh).
#include <gtest/gtest.h>

#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // OpenMesh's headers, GCC 12
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <tiny_gltf.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "ifsforge/core/color.h"
#include "ifsforge/core/error.h"
#include "ifsforge/geometry/axes.h"
#include "ifsforge/io/gltf_instances.h"
#include "ifsforge/io/mesh.h"
#include "ifsforge/io/primitive_spec.h"
#include "ifsforge/vector/instances.h"
#include "ifsforge/vector/primitives.h"

using namespace ifsforge;

namespace {

std::string axes_temp_path(const std::string& name) { return ::testing::TempDir() + "ifsforge_axes_" + name; }

/// A tetrahedron with its apex at (1, 2, 3) straight above (1, 2, 0): z is its up.
TriangleMesh steeple() {
  TriangleMesh m;
  m.positions = {{0, 1, 0}, {2, 1, 0}, {1, 3, 0}, {1, 2, 3}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  m.colors = {{0.0f, 0.5f, 1.0f, 0.25f}, {0.04045f, 0.2f, 0.8f, 1.0f}, {0.5f, 0.5f, 0.5f, 1.0f}, {1, 1, 1, 1}};
  compute_normals(m);
  return m;
}

template <typename T>
std::vector<T> accessor_data(const tinygltf::Model& model, int index, int components) {
  const auto& accessor = model.accessors.at(index);
  const auto& view = model.bufferViews.at(accessor.bufferView);
  std::vector<T> out(accessor.count * components);
  std::memcpy(out.data(), model.buffers.at(view.buffer).data.data() + view.byteOffset + accessor.byteOffset,
              out.size() * sizeof(T));
  return out;
}

tinygltf::Model load_glb(const std::string& path) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warning, path)) << error;
  return model;
}

}  // namespace

TEST(Color, SrgbDecodingHasItsStandardValues) {
  EXPECT_EQ(srgb_to_linear(0.0), 0.0);
  EXPECT_DOUBLE_EQ(srgb_to_linear(1.0), 1.0);
  EXPECT_NEAR(srgb_to_linear(0.5), 0.21404114048223255, 1e-15);
  EXPECT_NEAR(srgb_to_linear(0.04045), 0.04045 / 12.92, 1e-15);  // the linear segment ends here...
  EXPECT_NEAR(srgb_to_linear(0.04045 + 1e-9), 0.04045 / 12.92, 1e-8);  // ...and the curve joins it
  EXPECT_EQ(srgb_to_linear(-0.5), 0.0);  // clamped
  EXPECT_DOUBLE_EQ(srgb_to_linear(2.0), 1.0);
  for (int i = 0; i <= 255; ++i) {
    EXPECT_NEAR(linear_to_srgb(srgb_to_linear(i / 255.0)), i / 255.0, 1e-12) << i;
    // The float instantiation (grids, vertex colours) agrees to float rounding.
    EXPECT_NEAR(srgb_to_linear(i / 255.0f), srgb_to_linear(double(i / 255.0f)), 4e-7 * srgb_to_linear(i / 255.0)) << i;
  }
}

TEST(Axes, FormatsHaveTheirReadersUpAxis) {
  EXPECT_EQ(default_up("a/b.GLB"), Up::y);
  EXPECT_EQ(default_up("b.obj"), Up::y);
  EXPECT_EQ(default_up("b.ply"), Up::z);
  EXPECT_EQ(parse_name<Up>("y"), Up::y);
  EXPECT_EQ(parse_name<Up>("z"), Up::z);
  EXPECT_THROW(parse_name<Up>("x", "--up"), InputError);
  // y up is a rotation (determinant +1): triangles keep their winding.
  const auto x = oriented(1, 0, 0, Up::y), y = oriented(0, 1, 0, Up::y), z = oriented(0, 0, 1, Up::y);
  EXPECT_EQ(z, (std::array<float, 3>{0, 1, 0}));
  const double det = x[0] * (y[1] * z[2] - y[2] * z[1]) - x[1] * (y[0] * z[2] - y[2] * z[0]) + x[2] * (y[0] * z[1] - y[1] * z[0]);
  EXPECT_EQ(det, 1.0);
}

TEST(Axes, GlbIsYUpWithLinearColorsByDefaultAndZUpOnRequest) {
  const TriangleMesh m = steeple();
  for (const Up up : {Up::y, Up::z}) {
    const std::string path = axes_temp_path(std::string("steeple_") + name_of(up) + ".glb");
    MeshWriteOptions options;
    if (up == Up::z) options.up = Up::z;
    write_mesh(path, m, options);
    const tinygltf::Model model = load_glb(path);
    const auto& primitive = model.meshes.at(0).primitives.at(0);
    const auto p = accessor_data<float>(model, primitive.attributes.at("POSITION"), 3);
    const auto n = accessor_data<float>(model, primitive.attributes.at("NORMAL"), 3);
    const auto c = accessor_data<float>(model, primitive.attributes.at("COLOR_0"), 4);
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
      const auto want = up == Up::y ? std::array<float, 3>{m.positions[v][0], m.positions[v][2], -m.positions[v][1]}
                                    : m.positions[v];
      const auto normal = oriented(m.normals[v], up);
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(p[3 * v + k], want[k]) << v;
        EXPECT_EQ(n[3 * v + k], normal[k]) << v;
        EXPECT_NEAR(c[4 * v + k], srgb_to_linear(m.colors[v][k]), 1e-7) << v;
      }
      EXPECT_EQ(c[4 * v + 3], m.colors[v][3]);  // alpha is not encoded
    }
    // The apex is the file's highest point along its up axis.
    const auto& bounds = model.accessors[primitive.attributes.at("POSITION")];
    EXPECT_EQ(bounds.maxValues[up == Up::y ? 1 : 2], 3.0);
    EXPECT_NEAR(c[4 * 2], 0.21404114, 1e-7);  // display 0.5
    std::remove(path.c_str());
  }
}

TEST(Axes, ObjIsYUpAndPlyZUpWithDisplayColors) {
  const TriangleMesh m = steeple();
  for (const char* ext : {"obj", "ply"}) {
    for (const std::optional<Up> up : {std::optional<Up>{}, std::optional<Up>{Up::y}, std::optional<Up>{Up::z}}) {
      const std::string path = axes_temp_path(std::string("steeple.") + ext);
      MeshWriteOptions options;
      options.up = up;
      write_mesh(path, m, options);
      const Up expected = up.value_or(std::string(ext) == "obj" ? Up::y : Up::z);
      OpenMesh::TriMesh_ArrayKernelT<> back;
      OpenMesh::IO::Options read = OpenMesh::IO::Options::VertexColor;
      back.request_vertex_colors();
      ASSERT_TRUE(OpenMesh::IO::read_mesh(back, path, read)) << ext;
      ASSERT_EQ(back.n_vertices(), 4u);
      for (std::size_t v = 0; v < 4; ++v) {
        const auto p = back.point(back.vertex_handle(static_cast<unsigned>(v)));
        const auto want = oriented(m.positions[v], expected);
        for (int k = 0; k < 3; ++k) EXPECT_EQ(p[k], want[k]) << ext << " vertex " << v;
      }
      if (std::string(ext) == "ply") {  // 8-bit display values, as PLY readers (Blender's) take them
        ASSERT_TRUE(read.vertex_has_color());
        const auto c = back.color(back.vertex_handle(2));
        EXPECT_NEAR(c[0], 128, 1);
      }
      std::remove(path.c_str());
    }
  }
}

TEST(Axes, GltfInstancesPlaceEachFrameInEitherAxes) {
  // Two maps with rotations about different axes: frames that are not the identity.
  const double c = std::cos(0.7) * 0.5, s = std::sin(0.7) * 0.5;
  const Ifs ifs("turned", ChannelLayout("xyz"),
                {AffineMap(3, {c, -s, 0, s, c, 0, 0, 0, 0.5}, {0, 0, 0}),
                 AffineMap(3, {0.5, 0, 0, 0, c, -s, 0, s, c}, {0.5, 0.2, 0.4})},
                {0.5, 0.5});
  InstanceOptions o;
  o.depth = 3;
  o.primitives = {parse_primitive("box")};
  const InstanceList list = instances(ifs, o);
  for (const Up up : {Up::y, Up::z}) {
    GltfInstanceOptions g;
    g.up = up;
    const std::string path = axes_temp_path(std::string("instances_") + name_of(up) + ".glb");
    write_gltf_instances(path, list, g);
    const tinygltf::Model model = load_glb(path);
    ASSERT_EQ(model.nodes.size(), 1 + list.size());
    for (std::size_t i = 0; i < list.size(); ++i) {
      const auto& n = model.nodes[1 + i];
      const auto t = oriented(list.positions[i], up);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(n.translation[k], t[k], 1e-6);
      // The node's rotation sends the file's image of each local axis e_k to the file's image
      // of the frame's axis k: the instance has our orientation whatever the file's axes.
      const double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
      const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                              {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                              {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
      const auto& f = list.frames[i];
      for (int axis = 0; axis < 3; ++axis) {
        const auto local = oriented(axis == 0, axis == 1, axis == 2, up);
        const auto frame = oriented(f[3 * axis], f[3 * axis + 1], f[3 * axis + 2], up);
        for (int row = 0; row < 3; ++row) {
          const double image = r[row][0] * local[0] + r[row][1] * local[1] + r[row][2] * local[2];
          EXPECT_NEAR(image, frame[row], 1e-5) << name_of(up) << " instance " << i << " axis " << axis;
        }
      }
    }
    std::remove(path.c_str());
  }
}
