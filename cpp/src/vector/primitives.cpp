#include "ifsforge/vector/primitives.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"

namespace ifsforge {
namespace {

using Vec2 = std::array<double, 2>;

struct Builder {
  TriangleMesh mesh;
  std::uint32_t vertex(double x, double y, double z, double nx, double ny, double nz) {
    mesh.positions.push_back({float(x), float(y), float(z)});
    const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
    mesh.normals.push_back({float(nx / len), float(ny / len), float(nz / len)});
    return static_cast<std::uint32_t>(mesh.positions.size() - 1);
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) { mesh.triangles.push_back({a, b, c}); }
  void quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    triangle(a, b, c);
    triangle(a, c, d);
  }
};

/// A flat convex polygon (counter-clockwise) as a fan facing +z.
void flat_polygon(Builder& b, const std::vector<Vec2>& corners) {
  const std::uint32_t first = static_cast<std::uint32_t>(b.mesh.positions.size());
  for (const Vec2& c : corners) b.vertex(c[0], c[1], 0, 0, 0, 1);
  for (std::uint32_t k = 1; k + 1 < corners.size(); ++k) b.triangle(first, first + k, first + k + 1);
}

/// The band between two counter-clockwise polygons with the same number of corners, the inner
/// one shrunk towards the same centre: a stroked outline facing +z.
void flat_ring(Builder& b, const std::vector<Vec2>& outer, const std::vector<Vec2>& inner) {
  const std::uint32_t first = static_cast<std::uint32_t>(b.mesh.positions.size());
  const std::uint32_t n = static_cast<std::uint32_t>(outer.size());
  for (std::uint32_t k = 0; k < n; ++k) {
    b.vertex(outer[k][0], outer[k][1], 0, 0, 0, 1);
    b.vertex(inner[k][0], inner[k][1], 0, 0, 0, 1);
  }
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t o0 = first + 2 * k, i0 = o0 + 1, o1 = first + 2 * ((k + 1) % n), i1 = o1 + 1;
    b.quad(i0, o0, o1, i1);
  }
}

/// A regular polygon around `centre` with inradius-preserving offset: the corners of `corners`
/// moved away from `centre` so that every edge moves outwards by `offset` (negative: inwards).
std::vector<Vec2> offset_polygon(const std::vector<Vec2>& corners, Vec2 centre, double inradius, double offset) {
  std::vector<Vec2> out;
  const double k = (inradius + offset) / inradius;
  for (const Vec2& c : corners) out.push_back({centre[0] + k * (c[0] - centre[0]), centre[1] + k * (c[1] - centre[1])});
  return out;
}

std::vector<Vec2> circle_corners(double radius, int segments) {
  std::vector<Vec2> out;
  for (int k = 0; k < segments; ++k) {
    const double a = 2.0 * M_PI * k / segments;
    out.push_back({radius * std::cos(a), radius * std::sin(a)});
  }
  return out;
}

// Eq. 95: the third vertex turns by 120 degrees from the base vector at q1.
const std::vector<Vec2> kTriangle = {{0.0, 0.0}, {1.0, 0.0}, {0.5, std::sqrt(3.0) / 2.0}};
const Vec2 kTriangleCentre = {0.5, std::sqrt(3.0) / 6.0};
const double kTriangleInradius = std::sqrt(3.0) / 6.0;
const std::vector<Vec2> kSquare = {{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}};

void sphere(Builder& b, int segments) {
  const int rings = std::max(2, segments / 2);
  for (int r = 0; r <= rings; ++r) {
    const double theta = M_PI * r / rings;
    for (int s = 0; s <= segments; ++s) {
      const double phi = 2.0 * M_PI * s / segments;
      const double x = std::sin(theta) * std::cos(phi), y = std::sin(theta) * std::sin(phi), z = std::cos(theta);
      b.vertex(x, y, z, x, y, z);
    }
  }
  const int row = segments + 1;
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const std::uint32_t a = r * row + s, c = (r + 1) * row + s;
      if (r > 0) b.triangle(a, c, a + 1);
      if (r + 1 < rings) b.triangle(a + 1, c, c + 1);
    }
}

void box(Builder& b) {
  const double h = 1.0 / std::sqrt(3.0);  // the cube inscribed in the unit ball
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2) {
      // Two tangent axes u, v with u x v = the outward normal.
      const int u = (axis + (sign > 0 ? 1 : 2)) % 3, v = (axis + (sign > 0 ? 2 : 1)) % 3;
      std::uint32_t idx[4];
      const double corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (int k = 0; k < 4; ++k) {
        double p[3] = {0, 0, 0}, n[3] = {0, 0, 0};
        p[axis] = sign * h;
        p[u] = corners[k][0] * h;
        p[v] = corners[k][1] * h;
        n[axis] = sign;
        idx[k] = b.vertex(p[0], p[1], p[2], n[0], n[1], n[2]);
      }
      b.quad(idx[0], idx[1], idx[2], idx[3]);
    }
}

/// A disc cap at x = `x` facing `facing` (+1 or -1 along x).
void cap(Builder& b, double x, double radius, int facing, int segments) {
  const std::uint32_t centre = b.vertex(x, 0, 0, facing, 0, 0);
  const std::uint32_t first = static_cast<std::uint32_t>(b.mesh.positions.size());
  for (int s = 0; s < segments; ++s) {
    const double a = 2.0 * M_PI * s / segments;
    b.vertex(x, radius * std::cos(a), radius * std::sin(a), facing, 0, 0);
  }
  for (int s = 0; s < segments; ++s) {
    const std::uint32_t p = first + s, q = first + (s + 1) % segments;
    if (facing > 0) b.triangle(centre, p, q); else b.triangle(centre, q, p);
  }
}

/// The side of a (truncated) cone along x from (x0, r0) to (x1, r1), smooth normals.
void side(Builder& b, double x0, double r0, double x1, double r1, int segments) {
  const double slope = (r0 - r1) / (x1 - x0);  // normal's x component per unit radial
  const std::uint32_t first = static_cast<std::uint32_t>(b.mesh.positions.size());
  for (int s = 0; s <= segments; ++s) {
    const double a = 2.0 * M_PI * s / segments, c = std::cos(a), sn = std::sin(a);
    b.vertex(x0, r0 * c, r0 * sn, slope, c, sn);
    b.vertex(x1, r1 * c, r1 * sn, slope, c, sn);
  }
  for (int s = 0; s < segments; ++s) {
    const std::uint32_t a0 = first + 2 * s, a1 = a0 + 1, b0 = a0 + 2, b1 = a0 + 3;
    if (r1 > 0) b.quad(a0, b0, b1, a1); else b.triangle(a0, b0, a1);
  }
}

void torus(Builder& b, int segments) {
  const double major = 0.75, minor = 0.25;  // axis z, inscribed in the unit ball
  const int tube = std::max(6, segments / 2);
  for (int i = 0; i <= segments; ++i) {
    const double u = 2.0 * M_PI * i / segments;
    for (int j = 0; j <= tube; ++j) {
      const double v = 2.0 * M_PI * j / tube;
      const double nx = std::cos(v) * std::cos(u), ny = std::cos(v) * std::sin(u), nz = std::sin(v);
      b.vertex(major * std::cos(u) + minor * nx, major * std::sin(u) + minor * ny, minor * nz, nx, ny, nz);
    }
  }
  const int row = tube + 1;
  for (int i = 0; i < segments; ++i)
    for (int j = 0; j < tube; ++j) {
      const std::uint32_t a = i * row + j, c = (i + 1) * row + j;
      b.quad(a, c, c + 1, a + 1);
    }
}

}  // namespace

std::string Primitive::name() const {
  const std::string suffix = outline ? "-outline" : "";
  switch (shape) {
    case Shape::Line: return "line";
    case Shape::Circle: return "circle" + suffix;
    case Shape::Triangle: return "triangle" + suffix;
    case Shape::Square: return "square" + suffix;
    case Shape::Sphere: return "sphere";
    case Shape::Box: return "box";
    case Shape::Cone: return "cone";
    case Shape::Cylinder: return "cylinder";
    case Shape::Torus: return "torus";
    case Shape::Mesh: return "mesh:" + mesh_path;
  }
  return "?";
}

double Primitive::bounding_radius() const {
  const double half = kStrokeWidth / 2.0;
  switch (shape) {
    case Shape::Line: return std::hypot(1.0, half);
    case Shape::Circle: return 1.0 + (outline ? half : 0.0);
    case Shape::Triangle: return 1.0 + (outline ? 2.0 * half : 0.0);  // corners move by 2x the edge offset
    case Shape::Square: return std::sqrt(2.0) + (outline ? std::sqrt(2.0) * half : 0.0);
    case Shape::Mesh: {
      double r = 0.0;
      for (const auto& p : mesh->positions) r = std::max(r, std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]));
      return r;
    }
    default: return 1.0;
  }
}

const std::vector<std::string>& builtin_primitive_names() {
  static const std::vector<std::string> names = {
      "line", "circle", "circle-outline", "triangle", "triangle-outline", "square", "square-outline",
      "sphere", "box", "cone", "cylinder", "torus"};
  return names;
}

TriangleMesh primitive_mesh(const Primitive& p, int segments) {
  segments = std::max(segments, 6);
  Builder b;
  const double half = kStrokeWidth / 2.0;
  switch (p.shape) {
    case Shape::Line:
      flat_polygon(b, {{0.0, -half}, {1.0, -half}, {1.0, half}, {0.0, half}});
      break;
    case Shape::Circle:
      if (p.outline)
        flat_ring(b, circle_corners(1.0 + half, segments), circle_corners(1.0 - half, segments));
      else
        flat_polygon(b, circle_corners(1.0, segments));
      break;
    case Shape::Triangle:
      if (p.outline)
        flat_ring(b, offset_polygon(kTriangle, kTriangleCentre, kTriangleInradius, half),
                  offset_polygon(kTriangle, kTriangleCentre, kTriangleInradius, -half));
      else
        flat_polygon(b, kTriangle);
      break;
    case Shape::Square:
      if (p.outline)
        flat_ring(b, offset_polygon(kSquare, {0.5, 0.5}, 0.5, half), offset_polygon(kSquare, {0.5, 0.5}, 0.5, -half));
      else
        flat_polygon(b, kSquare);
      break;
    case Shape::Sphere:
      sphere(b, segments);
      break;
    case Shape::Box:
      box(b);
      break;
    case Shape::Cone:
      // Inscribed in the unit ball: apex at x = 1, base circle at x = -1/2 of radius sqrt(3)/2.
      side(b, -0.5, std::sqrt(3.0) / 2.0, 1.0, 0.0, segments);
      cap(b, -0.5, std::sqrt(3.0) / 2.0, -1, segments);
      break;
    case Shape::Cylinder: {
      const double h = 1.0 / std::sqrt(2.0);  // half-length = radius: inscribed in the unit ball
      side(b, -h, h, h, h, segments);
      cap(b, -h, h, -1, segments);
      cap(b, h, h, +1, segments);
      break;
    }
    case Shape::Torus:
      torus(b, segments);
      break;
    case Shape::Mesh:
      return *p.mesh;
  }
  return b.mesh;
}

}  // namespace ifsforge
