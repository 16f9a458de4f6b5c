// Vector IFS: instance counts, positions and vectors checked against independent compositions,
// the address algorithms against each other, primitives against their analytic volumes, and the
// exporters against their consumers (real POV-Ray, tinygltf's reader, the SVG text).
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

using namespace ifsforge;

namespace {

// Rotations about different axes make the maps non-commuting, so the order of an address matters.
AffineMap rotated(double scale, double degrees, int axis, std::array<double, 3> offset) {
  const double c = std::cos(degrees * M_PI / 180.0) * scale, s = std::sin(degrees * M_PI / 180.0) * scale;
  std::vector<double> m(9, 0.0);
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  m[axis * 3 + axis] = scale;
  m[a * 3 + a] = c;
  m[a * 3 + b] = -s;
  m[b * 3 + a] = s;
  m[b * 3 + b] = c;
  return AffineMap(3, m, {offset[0], offset[1], offset[2]});
}

Ifs twisted_tetrahedron() {
  return Ifs("twisted tetrahedron", ChannelLayout("xyz"),
             {rotated(0.5, 20, 2, {0, 0, 0}), rotated(0.5, -35, 0, {0.5, 0, 0}), rotated(0.45, 50, 1, {0.25, 0.45, 0}),
              rotated(0.5, 10, 2, {0.25, 0.15, 0.45})},
             {0.2, 0.3, 0.1, 0.4});
}

Ifs sierpinski_triangle() {
  return Ifs("sierpinski", ChannelLayout("xy"),
             {AffineMap(2, {0.5, 0, 0, 0.5}, {0, 0}), AffineMap(2, {0.5, 0, 0, 0.5}, {0.5, 0}),
              AffineMap(2, {0.5, 0, 0, 0.5}, {0.25, std::sqrt(3.0) / 4})},
             {1, 1, 1});
}

Ifs sample(const std::string& name) {
  return read_ifs_json(std::string(IFSFORGE_SOURCE_DIR) + "/samples/systems/" + name);
}

/// w_{a0} o w_{a1} o ... o w_{a_{L-1}} built with AffineMap::compose (not the walker's code).
AffineMap composition(const Ifs& ifs, const std::uint16_t* address, int length) {
  AffineMap m(ifs.dim());
  for (int i = 0; i < length; ++i) m = m.compose(ifs.map(address[i]));
  return m;
}

InstanceOptions explicit_base(int depth) {
  InstanceOptions o;
  o.depth = depth;
  o.base_point = {0.3, 0.2, 0.1};
  o.base_vector = {0.4, 0.1, -0.2};
  o.base_up = {0.0, 0.3, 0.5};
  return o;
}

/// A fresh folder per test run (scenes get their ifsforge.inc written beside them).
std::string temp_path(const std::string& name) {
  static const std::string folder = [] {
    std::string pattern = "/tmp/ifsforge_test_vector_XXXXXX";
    if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    return pattern;
  }();
  return folder + "/" + name;
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(VectorInstances, CountIsNToTheL) {
  EXPECT_EQ(instances(twisted_tetrahedron(), explicit_base(5)).size(), 1024u);  // 4^5
  InstanceOptions o;
  o.depth = 6;
  EXPECT_EQ(instances(sierpinski_triangle(), o).size(), 729u);  // 3^6
  o.depth = 2;
  const InstanceList sponge = instances(sample("menger_sponge.json"), o);
  EXPECT_EQ(sponge.size(), 400u);  // 20^2
  EXPECT_EQ(sponge.addresses.depth, 2);
  for (std::size_t i = 0; i < sponge.size(); ++i) ASSERT_EQ(sponge.addresses.lengths[i], 2);
  EXPECT_EQ(count_leaves(twisted_tetrahedron(), 7), 16384u);
}

TEST(VectorInstances, PositionIsTheCompositionOfTheAddressAppliedToTheBasePoint) {
  const Ifs ifs = twisted_tetrahedron();
  const InstanceOptions o = explicit_base(4);
  const InstanceList list = instances(ifs, o);
  Point q0{};
  for (int c = 0; c < 3; ++c) q0[c] = o.base_point[c];
  std::size_t reversed_differs = 0;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::uint16_t* a = list.addresses.address(i);
    const Point p = composition(ifs, a, 4)(q0);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(list.positions[i][c], p[c], 1e-6) << list.addresses.to_string(i);
    const std::uint16_t r[4] = {a[3], a[2], a[1], a[0]};
    const Point q = composition(ifs, r, 4)(q0);
    reversed_differs += std::abs(q[0] - p[0]) + std::abs(q[1] - p[1]) + std::abs(q[2] - p[2]) > 1e-4;
  }
  EXPECT_GT(reversed_differs, list.size() / 2) << "the test system must make the address order matter";
  // Depth-first order: addresses increase lexicographically and enumerate every digit string.
  for (std::size_t i = 1; i < list.size(); ++i)
    ASSERT_TRUE(std::lexicographical_compare(list.addresses.address(i - 1), list.addresses.address(i - 1) + 4,
                                             list.addresses.address(i), list.addresses.address(i) + 4));
}

TEST(VectorInstances, ConstantNormalisationGivesTheRequestedLength) {
  const Ifs ifs = twisted_tetrahedron();
  InstanceOptions o = explicit_base(3);
  o.normalisation = Normalisation::Constant;
  o.length = 0.125;
  const InstanceList list = instances(ifs, o);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const AffineMap m = composition(ifs, list.addresses.address(i), 3);
    // The pushed vector q1' - q0' (Eq. 60-62): its direction, drawn with the requested length.
    double t[3] = {0, 0, 0}, len = 0;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) t[r] += m.a(r, c) * o.base_vector[c];
      len += t[r] * t[r];
    }
    len = std::sqrt(len);
    const auto& f = list.frames[i];
    double drawn = 0;
    for (int c = 0; c < 3; ++c) {
      const double qh = list.positions[i][c] + list.scales[i] * f[c];  // qh = q0 + d (cos a, sin a, ...)
      const double expected = list.positions[i][c] + o.length * t[c] / len;
      ASSERT_NEAR(qh, expected, 1e-6);
      drawn += (qh - list.positions[i][c]) * (qh - list.positions[i][c]);
    }
    ASSERT_NEAR(std::sqrt(drawn), 0.125, 1e-6);
  }
}

TEST(VectorInstances, ProportionalNormalisationIsEq60) {
  const Ifs ifs = twisted_tetrahedron();
  InstanceOptions o = explicit_base(3);
  o.scale_factor = 1.75;
  const InstanceList list = instances(ifs, o);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const AffineMap m = composition(ifs, list.addresses.address(i), 3);
    Point q0{}, q1{};
    for (int c = 0; c < 3; ++c) {
      q0[c] = o.base_point[c];
      q1[c] = o.base_point[c] + o.base_vector[c];
    }
    const Point a = m(q0), b = m(q1);
    const double distance = std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
    ASSERT_NEAR(list.scales[i], 1.75 * distance, 1e-6);  // d = sf |q1 - q0|
  }
}

TEST(VectorInstances, FramesAreRotationsAndFollowTheVector) {
  const InstanceList list3 = instances(twisted_tetrahedron(), explicit_base(3));
  for (const auto& f : list3.frames) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const double dot = f[3 * a] * f[3 * b] + f[3 * a + 1] * f[3 * b + 1] + f[3 * a + 2] * f[3 * b + 2];
        ASSERT_NEAR(dot, a == b ? 1.0 : 0.0, 1e-6);
      }
    const double det = f[0] * (f[4] * f[8] - f[5] * f[7]) - f[1] * (f[3] * f[8] - f[5] * f[6]) + f[2] * (f[3] * f[7] - f[4] * f[6]);
    ASSERT_NEAR(det, 1.0, 1e-6);
  }
  // 2D with a reflection in the system: still rotations, e2 = e1 turned by +90 degrees, e3 = z.
  const Ifs mirrored("mirrored", ChannelLayout("xy"),
                     {AffineMap(2, {-0.5, 0, 0, 0.5}, {1, 0}), AffineMap(2, {0, -0.5, 0.5, 0}, {0, 0.5})}, {1, 1});
  InstanceOptions o;
  o.depth = 4;
  const InstanceList list2 = instances(mirrored, o);
  for (const auto& f : list2.frames) {
    ASSERT_NEAR(f[3], -f[1], 1e-7);
    ASSERT_NEAR(f[4], f[0], 1e-7);
    ASSERT_EQ(f[8], 1.0f);
  }
}

TEST(VectorInstances, TriangleThirdVertexIsEq95) {
  const Ifs ifs("rotating", ChannelLayout("xy"),
                {AffineMap(2, {0.4, -0.3, 0.3, 0.4}, {0, 0}), AffineMap(2, {0.5, 0.1, -0.1, 0.5}, {0.6, 0.2})}, {1, 1});
  InstanceOptions o;
  o.depth = 3;
  o.base_point = {0.1, 0.0};
  o.base_vector = {1.0, 0.0};
  o.primitives = {parse_primitive("triangle")};
  const InstanceList list = instances(ifs, o);
  const TriangleMesh tri = primitive_mesh(list.primitives[0]);
  ASSERT_EQ(tri.positions.size(), 3u);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const AffineMap m = composition(ifs, list.addresses.address(i), 3);
    const Point q0 = m(Point{0.1, 0.0}), q1 = m(Point{1.1, 0.0});
    const double a = std::atan2(q1[1] - q0[1], q1[0] - q0[0]);  // Eq. 61 (with the quadrant)
    const double d = std::hypot(q1[0] - q0[0], q1[1] - q0[1]);  // Eq. 60 with sf = 1
    // Eq. 95 (its garbled print restored): the third vertex turns by 120 degrees at q1.
    const double x2 = q1[0] + d * std::cos(a + 2 * M_PI / 3), y2 = q1[1] + d * std::sin(a + 2 * M_PI / 3);
    const auto& f = list.frames[i];
    const auto& l = tri.positions[2];
    const double wx = list.positions[i][0] + list.scales[i] * (l[0] * f[0] + l[1] * f[3]);
    const double wy = list.positions[i][1] + list.scales[i] * (l[0] * f[1] + l[1] * f[4]);
    ASSERT_NEAR(wx, x2, 1e-6);
    ASSERT_NEAR(wy, y2, 1e-6);
  }
}

TEST(VectorInstances, IdenticalForOneAndTwoThreads) {
  for (double pv : {0.0, 2e-4}) {
    InstanceOptions o = explicit_base(6);
    o.min_probability = pv;
    o.threads = 1;
    const InstanceList a = instances(twisted_tetrahedron(), o);
    o.threads = 2;
    const InstanceList b = instances(twisted_tetrahedron(), o);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.positions.data(), b.positions.data(), a.size() * 12), 0);
    EXPECT_EQ(std::memcmp(a.frames.data(), b.frames.data(), a.size() * 36), 0);
    EXPECT_EQ(a.scales, b.scales);
    EXPECT_EQ(a.addresses.digits, b.addresses.digits);
    EXPECT_EQ(a.addresses.probabilities, b.addresses.probabilities);
  }
}

TEST(VectorAddresses, StringRewritingTsaAndVrrGiveTheSameAddresses) {
  const Ifs ifs = twisted_tetrahedron();
  std::vector<std::string> strings = string_rewriting(ifs, 4);
  ASSERT_EQ(strings.size(), 256u);
  // The seed's order: the newest (outermost) digit varies fastest.
  EXPECT_EQ(strings[0], "0.0.0.0");
  EXPECT_EQ(strings[1], "1.0.0.0");
  const AddressLeaves tsa = tesseral_synecdoche(ifs, 4, 0.0, {0.3, 0.2, 0.1});
  const InstanceList vrr = instances(ifs, explicit_base(4));
  ASSERT_EQ(tsa.addresses.size(), 256u);
  std::vector<std::string> tsa_strings;
  for (std::size_t i = 0; i < tsa.addresses.size(); ++i) {
    tsa_strings.push_back(tsa.addresses.to_string(i));
    EXPECT_EQ(tsa_strings.back(), vrr.addresses.to_string(i));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(tsa.points[i * 3 + c], vrr.positions[i][c], 1e-6);
  }
  std::sort(strings.begin(), strings.end());
  EXPECT_EQ(strings, tsa_strings);  // the TSA already lists them sorted
  EXPECT_EQ(std::set<std::string>(strings.begin(), strings.end()).size(), 256u);
}

TEST(VectorAddresses, PrunedLeavesPartitionTheInvariantMeasure) {
  const Ifs ifs = twisted_tetrahedron();
  const double pv = 1e-3;
  const AddressLeaves t = tesseral_synecdoche(ifs, 12, pv);
  const auto& p = ifs.probabilities();
  double total = 0.0;
  std::set<int> lengths;
  for (std::size_t i = 0; i < t.addresses.size(); ++i) {
    const int len = t.addresses.lengths[i];
    const double prob = t.addresses.probabilities[i];
    total += prob;
    lengths.insert(len);
    double product = 1.0;
    for (int k = 0; k < len; ++k) product *= p[t.addresses.address(i)[k]];
    ASSERT_NEAR(prob, product, 1e-15);
    ASSERT_TRUE(len == 12 || prob < pv) << t.addresses.to_string(i);
    ASSERT_GE(prob / p[t.addresses.address(i)[len - 1]], pv) << "the parent should have been a leaf";
    for (int k = len; k < 12; ++k) ASSERT_EQ(t.addresses.address(i)[k], kNoMap);
  }
  EXPECT_NEAR(total, 1.0, 1e-9);  // the leaves' pieces partition the attractor's measure
  EXPECT_GT(lengths.size(), 2u);
  EXPECT_EQ(count_leaves(ifs, 12, pv), t.addresses.size());
  InstanceOptions o = explicit_base(12);
  o.min_probability = pv;
  const InstanceList list = instances(ifs, o);
  EXPECT_EQ(list.addresses.digits, t.addresses.digits);
}

TEST(VectorInstances, IndexChannelSelectsThePrimitiveEq107) {
  // xyz+rgb+k (Eq. 106): spatial Sierpinski tetrahedron, colours constant per map, and
  // I' = a77 I + b7 with b7 = map index.
  auto map7 = [](std::array<double, 3> t, std::array<double, 3> rgb, double a77, double b7) {
    std::vector<double> m(49, 0.0);
    for (int c = 0; c < 3; ++c) m[c * 7 + c] = 0.5;
    m[6 * 7 + 6] = a77;
    return AffineMap(7, m, {t[0], t[1], t[2], rgb[0], rgb[1], rgb[2], b7});
  };
  for (double a77 : {0.0, 0.6}) {
    const Ifs ifs("7d", ChannelLayout("xyz+rgb+k"),
                  {map7({0, 0, 0}, {1, 0, 0}, a77, 0), map7({0.5, 0, 0}, {0, 1, 0}, a77, 1),
                   map7({0.25, 0.5, 0}, {0, 0, 1}, a77, 2), map7({0.25, 0.2, 0.5}, {1, 1, 0}, a77, 3)},
                  {1, 1, 1, 1});
    InstanceOptions o;
    o.depth = 3;
    o.primitives = parse_primitives("sphere, box, cone");
    o.base_point = {0.5, 0.5, 0.5, 0, 0, 0, 0};
    const InstanceList list = instances(ifs, o);
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::uint16_t* a = list.addresses.address(i);
      const Point p = composition(ifs, a, 3)(Point{0.5, 0.5, 0.5, 0, 0, 0, 0});
      const long long k = std::llround(p[6]);
      ASSERT_EQ(list.primitive[i], static_cast<std::uint16_t>(k % 3)) << list.addresses.to_string(i);
      if (a77 == 0.0) {
        ASSERT_EQ(list.primitive[i], a[0] % 3);  // constant per (outermost) map
      }
      // Eq. 101: colours normalised by the attractor's range of each channel, here [0, 1].
      const float expected[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}};
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(list.colors[i][c], expected[a[0]][c], 1e-6);
    }
  }
}

TEST(VectorInstances, IndexChannelFollowsPositionEq99) {
  // xyz+k (Eq. 98-99): G' = a41 x + a44 G + b4 with a41 = 3 makes the primitive position-dependent.
  auto map4 = [](std::array<double, 3> t, double b4) {
    return AffineMap(4, {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 3.0, 0, 0, 0.25}, {t[0], t[1], t[2], b4});
  };
  const Ifs ifs("4d", ChannelLayout("xyz+k"),
                {map4({0, 0, 0}, 0), map4({0.5, 0, 0}, 1), map4({0.25, 0.5, 0}, 0), map4({0.25, 0.2, 0.5}, 2)}, {1, 1, 1, 1});
  InstanceOptions o;
  o.depth = 4;
  o.primitives = parse_primitives("sphere,box,cone,cylinder,torus");
  o.base_point = {0.1, 0.2, 0.3, 0.4};
  const InstanceList list = instances(ifs, o);
  std::set<int> used;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Point p = composition(ifs, list.addresses.address(i), 4)(Point{0.1, 0.2, 0.3, 0.4});
    const long long k = std::llround(p[3]);
    ASSERT_EQ(list.primitive[i], static_cast<std::uint16_t>(((k % 5) + 5) % 5));
    used.insert(list.primitive[i]);
  }
  EXPECT_GE(used.size(), 4u);
}

TEST(VectorInstances, BadInputIsRefusedWithAClearMessage) {
  const Ifs ifs = twisted_tetrahedron();
  auto message = [&](InstanceOptions o) -> std::string {
    try {
      instances(ifs, o);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  InstanceOptions o;
  o.depth = 65;
  EXPECT_NE(message(o).find("depth"), std::string::npos);
  o = InstanceOptions{};
  o.min_probability = 1.0;
  EXPECT_NE(message(o).find("pv"), std::string::npos);
  o = InstanceOptions{};
  o.base_vector = {1, 0};
  EXPECT_NE(message(o).find("base vector needs 3"), std::string::npos);
  o.base_vector = {0, 0, 0};
  EXPECT_NE(message(o).find("must not be zero"), std::string::npos);
  o = InstanceOptions{};
  o.base_point = {0, 0};
  EXPECT_NE(message(o).find("base point needs 3"), std::string::npos);
  o = InstanceOptions{};
  o.color_source = ColorSource::Channels;
  EXPECT_NE(message(o).find("no colour channels"), std::string::npos);
  o = InstanceOptions{};
  o.scale_factor = 0;
  EXPECT_NE(message(o).find("scale factor"), std::string::npos);
  o = InstanceOptions{};
  o.depth = 40;  // 4^40 > 10^18
  EXPECT_NE(message(o).find("10^18"), std::string::npos);
  EXPECT_THROW(parse_primitive("dodecahedron"), InputError);
  EXPECT_THROW(parse_primitive("sphere-outline"), InputError);
  EXPECT_THROW(parse_primitive("mesh:/nonexistent/leaf.ply"), FileError);
  Ifs recurrent = sierpinski_triangle();
  recurrent.set_transitions(TransitionMatrix(3, {0, 0.5, 0.5, 0.5, 0, 0.5, 0.5, 0.5, 0}));
  try {
    instances(recurrent, InstanceOptions{});
    ADD_FAILURE() << "a recurrent IFS has another address tree";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("recurrent"), std::string::npos);
  }
  setenv("IFSFORGE_MEMORY_BUDGET_MB", "64", 1);
  o = InstanceOptions{};
  o.depth = 14;  // 4^14 = 268M instances
  EXPECT_THROW(instances(ifs, o), MemoryBudgetError);
  unsetenv("IFSFORGE_MEMORY_BUDGET_MB");
}

TEST(VectorPrimitives, MeshesAreClosedOutwardAndHaveTheAnalyticVolume) {
  const double r2 = 1.0 / std::sqrt(2.0), h3 = std::sqrt(3.0) / 2.0;
  const std::map<std::string, double> volume = {
      {"sphere", 4.0 / 3.0 * M_PI}, {"box", std::pow(2.0 / std::sqrt(3.0), 3)}, {"cylinder", M_PI * r2 * r2 * 2 * r2},
      {"cone", M_PI * h3 * h3 * 1.5 / 3.0}, {"torus", 2 * M_PI * M_PI * 0.75 * 0.25 * 0.25}};
  for (const auto& [name, expected] : volume) {
    const Primitive p = parse_primitive(name);
    const TriangleMesh m = primitive_mesh(p, 96);
    double v = 0.0;  // divergence theorem: positive only if every triangle faces outwards
    for (const auto& t : m.triangles) {
      const auto& a = m.positions[t[0]];
      const auto& b = m.positions[t[1]];
      const auto& c = m.positions[t[2]];
      v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
    }
    EXPECT_NEAR(v, expected, 0.01 * expected) << name;
    for (const auto& q : m.positions) ASSERT_LE(std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]), p.bounding_radius() + 1e-6) << name;
  }
  // Flat shapes: areas of the filled shapes and of the stroked bands.
  auto area = [](const TriangleMesh& m) {
    double s = 0.0;
    for (const auto& t : m.triangles) {
      const auto& a = m.positions[t[0]];
      const auto& b = m.positions[t[1]];
      const auto& c = m.positions[t[2]];
      s += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    }
    return s;
  };
  const double w = kStrokeWidth;
  EXPECT_NEAR(area(primitive_mesh(parse_primitive("triangle"))), std::sqrt(3.0) / 4, 1e-6);
  EXPECT_NEAR(area(primitive_mesh(parse_primitive("square"))), 1.0, 1e-6);
  EXPECT_NEAR(area(primitive_mesh(parse_primitive("line"))), w, 1e-6);
  EXPECT_NEAR(area(primitive_mesh(parse_primitive("square-outline"))), 4.0 * w, 1e-6);  // (1+w)^2 - (1-w)^2
  EXPECT_NEAR(area(primitive_mesh(parse_primitive("circle-outline"), 512)), 2 * M_PI * w, 1e-3);
}

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
