// Vector IFS: instance counts, positions and vectors checked against independent compositions,
// the address algorithms against each other, primitives against their analytic volumes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
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

TEST(VectorInstances, ConstantNormalizationGivesTheRequestedLength) {
  const Ifs ifs = twisted_tetrahedron();
  InstanceOptions o = explicit_base(3);
  o.normalization = Normalization::Constant;
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

TEST(VectorInstances, ProportionalNormalizationIsEq60) {
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
  EXPECT_NE(message(o).find("no color channels"), std::string::npos);
  o = InstanceOptions{};
  o.scale_factor = 0;
  EXPECT_NE(message(o).find("scale factor"), std::string::npos);
  o = InstanceOptions{};
  o.depth = 40;  // 4^40 = 10^24 leaves
  EXPECT_NE(message(o).find("depth: 4^40 = 10^24 leaves, more than 10^12"), std::string::npos);
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
