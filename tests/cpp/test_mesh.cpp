// The mesh writers: what is written reads back with the same counts and values.
#include <gtest/gtest.h>
#include <unistd.h>

#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // OpenMesh's headers, GCC 12
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <fstream>
#include <tiny_gltf.h>

#include "ifsforge/core/error.h"
#include "ifsforge/io/mesh.h"
#include "ifsforge/geometry/mesh_edges.h"
#include "ifsforge/io/png.h"

using namespace ifsforge;

namespace {

TriangleMesh cube() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) {
    m.positions.push_back({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
    m.colors.push_back({float(i & 1), 0.5f, float(i >> 2), 1.0f});
    m.uvs.push_back({float(i & 1), float((i >> 1) & 1)});
  }
  // Two triangles per face, counter-clockwise from outside.
  const std::uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  compute_normals(m);
  return m;
}

std::string mesh_temp_path(const std::string& name) { return ::testing::TempDir() + "ifsforge_mesh_" + name; }

}  // namespace

TEST(Mesh, NormalsPointOutOfTheCube) {
  const TriangleMesh m = cube();
  for (std::size_t i = 0; i < m.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      // Corner (0, *, *) has a normal with negative x, etc.
      EXPECT_EQ(m.normals[i][k] > 0, m.positions[i][k] > 0.5f);
      EXPECT_NEAR(std::abs(m.normals[i][k]), 1.0 / std::sqrt(3.0), 1e-6);
    }
}

TEST(Mesh, PlyAndObjReadBackThroughOpenMesh) {
  for (const char* ext : {"ply", "obj"}) {
    const std::string path = mesh_temp_path(std::string("cube.") + ext);
    write_mesh(path, cube());
    OpenMesh::TriMesh_ArrayKernelT<> back;
    OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexColor;
    back.request_vertex_colors();
    ASSERT_TRUE(OpenMesh::IO::read_mesh(back, path, options)) << ext;
    EXPECT_EQ(back.n_vertices(), 8u) << ext;
    EXPECT_EQ(back.n_faces(), 12u) << ext;
    if (std::string(ext) == "ply") {
      ASSERT_TRUE(options.vertex_has_color());
      const auto c = back.color(back.vertex_handle(5));  // (1, 0, 1): colour (1, .5, 1)
      EXPECT_EQ(c[0], 255);
      EXPECT_NEAR(c[1], 128, 1);
    }
    std::remove(path.c_str());
  }
}

TEST(Mesh, GlbReadsBackWithItsTexture) {
  const std::string png = mesh_temp_path("texture.png");
  write_png(png, Image(4, 1, 3));
  MeshWriteOptions options;
  options.base_color_texture = png;
  const std::string path = mesh_temp_path("cube.glb");
  write_mesh(path, cube(), options);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, path)) << err;
  const auto& primitive = model.meshes.at(0).primitives.at(0);
  EXPECT_EQ(model.accessors[primitive.attributes.at("POSITION")].count, 8u);
  EXPECT_EQ(model.accessors[primitive.attributes.at("COLOR_0")].count, 8u);
  EXPECT_EQ(model.accessors[primitive.indices].count, 36u);
  ASSERT_EQ(model.images.size(), 1u);
  EXPECT_EQ(model.images[0].width, 4);  // tinygltf decoded our PNG
  std::remove(path.c_str());
  std::remove(png.c_str());
}

TEST(Mesh, BadMeshesAreRefusedAndNothingIsWritten) {
  TriangleMesh broken = cube();
  broken.triangles.push_back({0, 1, 99});
  const std::string path = mesh_temp_path("broken.glb");
  EXPECT_THROW(write_mesh(path, broken), InputError);
  EXPECT_NE(access(path.c_str(), F_OK), 0);
  TriangleMesh short_colors = cube();
  short_colors.colors.pop_back();
  EXPECT_THROW(write_mesh(mesh_temp_path("c.ply"), short_colors), InputError);
  EXPECT_THROW(write_mesh(mesh_temp_path("cube.stl"), cube()), InputError);
  EXPECT_THROW(write_mesh("/nonexistent/cube.ply", cube()), FileError);
}

// Two triangles sharing the diagonal of a square: 5 edges, the shared one once, sorted.
TEST(MeshEdges, SharedEdgeOnceSortedPerCorner) {
  const MeshEdges e = mesh_edges({0, 1, 2, 0, 2, 3}, 3, 4);
  const std::vector<std::array<std::uint32_t, 2>> edges{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {2, 3}};
  EXPECT_EQ(e.edges, edges);
  // Corners: (0,1) (1,2) (2,0) | (0,2) (2,3) (3,0).
  EXPECT_EQ(e.corner_edges, (std::vector<std::uint32_t>{0, 3, 1, 1, 4, 2}));
}

TEST(MeshEdges, ClosedSurfaceObeysEuler) {
  // An octahedron: V - E + F = 2 with 6 vertices and 8 faces gives 12 edges.
  const MeshEdges e = mesh_edges({0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5}, 3, 6);
  EXPECT_EQ(e.edges.size(), 12u);
  std::vector<int> uses(12, 0);
  for (auto k : e.corner_edges) ++uses[k];
  for (int u : uses) EXPECT_EQ(u, 2);  // closed: every edge between two faces
}

TEST(MeshEdges, BadIndicesAreInputErrors) {
  EXPECT_THROW(mesh_edges({0, 1, 7}, 3, 3), InputError);
  EXPECT_THROW(mesh_edges({0, 1, 1}, 3, 3), InputError);
  EXPECT_THROW(mesh_edges({0, 1, 2, 3}, 3, 4), InputError);  // not whole faces
}

// A 2x1 strip of quads: 7 edges, the middle one shared.
TEST(MeshEdges, Quads) {
  const MeshEdges e = mesh_edges({0, 1, 4, 3, 1, 2, 5, 4}, 4, 6);
  EXPECT_EQ(e.edges.size(), 7u);
  EXPECT_EQ(e.corner_edges[1], e.corner_edges[7]);  // (1,4) from both quads
}
