// Vector IFS exporters against their consumers (real POV-Ray, tinygltf's reader, the SVG text)
// and the 2D drawing.
#include <gtest/gtest.h>
#include <tiny_gltf.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/io/gltf_instances.h"
#include "ifsforge/io/ifs_json.h"
#include "ifsforge/io/png.h"
#include "ifsforge/io/pov_instances.h"
#include "ifsforge/io/pov_scene.h"
#include "ifsforge/io/povray.h"
#include "ifsforge/io/svg.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/vector/addresses.h"
#include "ifsforge/vector/draw.h"
#include "ifsforge/io/primitive_spec.h"
#include "ifsforge/vector/instances.h"
#include "vector_test.h"

using namespace ifsforge;
using namespace ifsforge::vector_test;

TEST(VectorPovray, NumberFormats) {
  char buffer[64];
  EXPECT_EQ(std::string(buffer, pov_vector(buffer, 0.5f, -2.0f, 1e-9f)), "<0.5,-2,1e-09>");
  EXPECT_EQ(std::string(buffer, pov_unit(buffer, 0.25f)), ".25");
  EXPECT_EQ(std::string(buffer, pov_unit(buffer, 1.5f)), "1");
}

TEST(VectorPovray, IncludeIsTheRepositoryCopy) {
  EXPECT_EQ(povray_include(), read_all(std::string(IFSFORGE_SOURCE_DIR) + "/povray/ifsforge.inc"))
      << "cpp/embed_bytes.cmake embeds povray/ifsforge.inc at build time";
}

namespace {

/// IoU of POV-Ray's non-background pixels with a PRR render of the same orthographic view.
double silhouette_iou(const Ifs& ifs, const InstanceList& list, const std::string& name, double yaw, double pitch) {
  const int w = 160, h = 120;
  PovSceneOptions o;
  o.width = w;
  o.height = h;
  o.view.yaw = yaw;
  o.view.pitch = pitch;
  o.view.orthographic = true;
  o.environment.floor = false;
  o.environment.sky = false;
  o.environment.background = {0, 0, 0};
  o.environment.quality = PovQuality::Draft;
  const std::string scene = temp_path(name + ".pov"), png = temp_path(name + ".png");
  write_pov_scene(scene, list, o);
  PovRenderOptions r;
  r.width = w;
  r.height = h;
  r.antialias = 0;
  render_povray(scene, png, r);
  const Image pov = read_png(png);
  // The same window on the same image plane for the point-recursive renderer.
  const PovFraming framing = frame_instances(list, o);
  const PovCamera& c = framing.camera;
  const double yr = yaw * M_PI / 180, pr = pitch * M_PI / 180;
  const double u[3] = {std::cos(yr), std::sin(yr), 0}, v[3] = {-std::sin(pr) * std::sin(yr), std::sin(pr) * std::cos(yr), std::cos(pr)};
  const double uc = u[0] * c.location[0] + u[1] * c.location[1] + u[2] * c.location[2];
  const double vc = v[0] * c.location[0] + v[1] * c.location[1] + v[2] * c.location[2];
  const double cw = std::sqrt(c.right[0] * c.right[0] + c.right[1] * c.right[1] + c.right[2] * c.right[2]);
  const double ch = std::sqrt(c.up[0] * c.up[0] + c.up[1] * c.up[1] + c.up[2] * c.up[2]);
  RenderOptions ro;
  ro.width = w;
  ro.height = h;
  ro.window = Window{uc - cw / 2, vc - ch / 2, uc + cw / 2, vc + ch / 2};
  ro.view = View{yaw, pitch};
  const Raster prr = renderer("prr").render(ifs, ro);
  std::size_t both = 0, either = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool a = prr.density[std::size_t(y) * w + x] > 0.0f;
      const bool b = pov.at(x, y, 0) + pov.at(x, y, 1) + pov.at(x, y, 2) > 0.0f;
      both += a && b;
      either += a || b;
    }
  std::remove(scene.c_str());
  std::remove(png.c_str());
  std::printf("[ silhouette IoU ] %s %.3f\n", name.c_str(), static_cast<double>(both) / either);
  return static_cast<double>(both) / either;
}

}  // namespace

TEST(VectorPovray, RenderedBoxesCoverTheMengerSpongeSilhouette) {
  const Ifs sponge = sample("menger_sponge.json");
  InstanceOptions o;
  o.depth = 2;
  o.primitives = {parse_primitive("box")};
  o.color = {1, 1, 1, 1};
  o.color_source = ColorSource::Constant;
  const double iou = silhouette_iou(sponge, instances(sponge, o), "sponge", 30, 25);
  EXPECT_GE(iou, 0.8);
}

TEST(VectorPovray, RenderedSpheresCoverTheTetrahedronSilhouette) {
  const Ifs ifs = twisted_tetrahedron();
  InstanceOptions o;
  o.depth = 7;
  o.color_source = ColorSource::Constant;
  const double iou = silhouette_iou(ifs, instances(ifs, o), "spheres", 40, 30);
  EXPECT_GE(iou, 0.8);
}

TEST(VectorPovray, HostileNamesStayInCommentsAndStrings) {
  Ifs ifs = sierpinski_triangle();
  ifs.set_name("\"; #system \"rm\n#declare Boom = 1/0;\n/* x");
  InstanceOptions o;
  o.depth = 3;
  const InstanceList list = instances(ifs, o);
  const std::string scene = temp_path("hostile.pov"), png = temp_path("hostile.png");
  PovSceneOptions so;
  so.width = 40;
  so.height = 30;
  write_pov_scene(scene, list, so);
  std::istringstream lines(read_all(scene));
  std::string line;
  int mentions = 0;
  while (std::getline(lines, line))
    if (line.find("system") != std::string::npos) {
      ++mentions;
      EXPECT_TRUE(line.rfind("// ", 0) == 0 || line.rfind("#declare IFS_Title = \"", 0) == 0) << line;
    }
  EXPECT_EQ(mentions, 2);
  EXPECT_EQ(read_all(scene).find("\n#declare Boom"), std::string::npos);
  PovRenderOptions r;
  r.width = 40;
  r.height = 30;
  EXPECT_NO_THROW(render_povray(scene, png, r));  // 1/0 would stop POV-Ray's parser
  EXPECT_EQ(access(png.c_str(), R_OK), 0);
  std::remove(scene.c_str());
  std::remove(png.c_str());
}

TEST(VectorPovray, SceneHasOneLinePerInstanceAndSameBytesForAnyThreads) {
  InstanceOptions io = explicit_base(5);
  io.primitives = parse_primitives("sphere,cone");
  const Ifs ifs = twisted_tetrahedron();
  const InstanceList list = instances(ifs, io);
  PovSceneOptions o;
  o.threads = 1;
  const std::string a = temp_path("a.pov"), b = temp_path("b.pov");
  write_pov_scene(a, list, o);
  o.threads = 2;
  write_pov_scene(b, list, o);
  const std::string text = read_all(a);
  EXPECT_EQ(text, read_all(b));
  std::size_t spheres = 0, objects = 0, pos = 0;
  while ((pos = text.find("\nsphere{", pos)) != std::string::npos) ++spheres, ++pos;
  pos = 0;
  while ((pos = text.find("\nobject{IFS_Sphere matrix", pos)) != std::string::npos) ++objects, ++pos;
  EXPECT_EQ(spheres + objects, 1024u);
  EXPECT_EQ(read_all(temp_path("ifsforge.inc")), povray_include());  // written beside the scene
  std::remove(a.c_str());
  std::remove(b.c_str());
}

TEST(VectorPovray, MissingPovrayOrBadSceneIsAFileError) {
  const std::string scene = temp_path("broken.pov");
  {
    std::ofstream out(scene);
    out << "#version 3.7;\nsphere { <0,0,0>, 1 pigment { rgb <1, 0, 0> } \n";  // unclosed
  }
  try {
    render_povray(scene, temp_path("broken.png"));
    FAIL() << "a broken scene must not render";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("POV-Ray failed"), std::string::npos) << e.what();
  }
  EXPECT_NE(access(temp_path("broken.png").c_str(), F_OK), 0);
  std::remove(scene.c_str());
}

TEST(VectorSvg, OneElementPerInstanceAnd3DIsRefused) {
  InstanceOptions o;
  o.depth = 4;
  o.primitives = parse_primitives("triangle,square-outline,circle,line");
  const Ifs ifs("xy+k", ChannelLayout("xy+k"),
                {AffineMap(3, {0.5, 0, 0, 0, 0.5, 0, 0, 0, 0}, {0, 0, 0}), AffineMap(3, {0.5, 0, 0, 0, 0.5, 0, 0, 0, 0}, {0.5, 0, 1}),
                 AffineMap(3, {0.5, 0, 0, 0, 0.5, 0, 0, 0, 0}, {0.25, 0.43, 2}), AffineMap(3, {0.3, 0, 0, 0, 0.3, 0, 0, 0, 0}, {0.35, 0.1, 3})},
                {1, 1, 1, 1});
  const InstanceList list = instances(ifs, o);
  const std::string path = temp_path("list.svg");
  write_svg(path, list);
  const std::string text = read_all(path);
  auto count = [&](const std::string& tag) {
    std::size_t n = 0, pos = 0;
    while ((pos = text.find(tag, pos)) != std::string::npos) ++n, ++pos;
    return n;
  };
  EXPECT_EQ(count("<polygon"), 2u * 64u);  // the outermost map picks the primitive: 64 each
  EXPECT_EQ(count("<circle"), 64u);
  EXPECT_EQ(count("<line"), 64u);
  EXPECT_EQ(count("stroke-linejoin=\"miter\""), 64u);
  std::remove(path.c_str());
  EXPECT_THROW(write_svg(path, instances(twisted_tetrahedron(), explicit_base(2))), InputError);
}

TEST(VectorGltf, TinyGltfReadsOneNodePerInstanceWithTheInstanceTransform) {
  const Ifs ifs = twisted_tetrahedron();
  InstanceOptions o = explicit_base(3);
  o.primitives = {parse_primitive("cone")};
  const InstanceList list = instances(ifs, o);
  const std::string path = temp_path("list.glb");
  write_gltf_instances(path, list);
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warning;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warning, path)) << error;
  ASSERT_EQ(model.nodes.size(), 1 + list.size());
  ASSERT_EQ(model.nodes[0].children.size(), list.size());
  EXPECT_EQ(model.meshes.size(), 4u);  // one cone mesh per colour class (four first-level maps)
  EXPECT_EQ(model.accessors.size(), 3u);  // the cone's geometry, stored once
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto& n = model.nodes[1 + i];
    EXPECT_EQ(n.name, list.addresses.to_string(i));
    // glTF y-up back to z-up: (x, y, z)_gltf = (x, z, -y)_ours.
    EXPECT_NEAR(n.translation[0], list.positions[i][0], 1e-6);
    EXPECT_NEAR(n.translation[1], list.positions[i][2], 1e-6);
    EXPECT_NEAR(n.translation[2], -list.positions[i][1], 1e-6);
    EXPECT_NEAR(n.scale[0], list.scales[i], 1e-6);
    // The rotation sends the local x axis (glTF x) to e1 in glTF axes.
    const double qx = n.rotation[0], qy = n.rotation[1], qz = n.rotation[2], qw = n.rotation[3];
    const double ex = 1 - 2 * (qy * qy + qz * qz), ey = 2 * (qx * qy + qz * qw), ez = 2 * (qx * qz - qy * qw);
    const auto& f = list.frames[i];
    EXPECT_NEAR(ex, f[0], 1e-5);
    EXPECT_NEAR(ey, f[2], 1e-5);
    EXPECT_NEAR(ez, -f[1], 1e-5);
  }
  std::remove(path.c_str());
}

TEST(VectorDraw, SierpinskiTrianglesCoverThreeQuartersToTheL) {
  // Base vector = the base edge of the attractor: the level-L triangles tile the level-L gasket.
  InstanceOptions o;
  o.depth = 5;
  o.base_point = {0, 0};
  o.base_vector = {1, 0};
  o.primitives = {parse_primitive("triangle")};
  o.color_source = ColorSource::Constant;
  o.color = {0, 0, 0, 1};
  const InstanceList list = instances(sierpinski_triangle(), o);
  DrawOptions d;
  d.width = 512;
  d.height = 512;
  d.window = Window{-0.25, -0.25, 1.25, 1.25};
  const Image image = draw_instances(list, d);
  double dark = 0.0;
  for (int y = 0; y < 512; ++y)
    for (int x = 0; x < 512; ++x) dark += 1.0 - image.at(x, y, 0);
  const double pixel_area = (1.5 / 512) * (1.5 / 512);
  const double expected = std::pow(0.75, 5) * std::sqrt(3.0) / 4.0;
  EXPECT_NEAR(dark * pixel_area, expected, 0.01 * expected);
  d.threads = 1;
  const Image one = draw_instances(list, d);
  EXPECT_EQ(one.pixels, image.pixels);
}
