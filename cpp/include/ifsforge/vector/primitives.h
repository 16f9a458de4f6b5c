#pragma once
/// @file The graphics primitives a vector IFS places (seed 6.1.3.5, 6.2.3.3-6.2.3.4, 6.3.3.2):
/// 2D lines, circles, equilateral triangles (Eq. 95) and squares, filled or outlined; 3D
/// spheres, boxes, cones, cylinders, tori; and any user mesh.
///
/// Every primitive lives in the frame of its instance: x along the instance's vector (the
/// normalised q0 -> qh of Eq. 60-62), y and z completing a right-handed frame, and one unit is
/// the vector's length d. The 2D shapes follow the seed: the vector is the line, the radius of
/// the circle, or the base edge of the triangle and the square, so they lie in the xy plane
/// with a vertex at the origin. The 3D shapes are centred on the origin and inscribed in the
/// unit ball (the seed's sphere: centre and radius), so d is the radius of their bounding ball.
#include <memory>
#include <string>
#include <vector>

#include "ifsforge/geometry/triangle_mesh.h"

namespace ifsforge {

enum class Shape { Line, Circle, Triangle, Square, Sphere, Box, Cone, Cylinder, Torus, Mesh };

/// Width of lines and outlines, in units of the instance's vector length d.
constexpr double kStrokeWidth = 0.06;

struct Primitive {
  Shape shape = Shape::Sphere;
  bool outline = false;   ///< circle, triangle, square: a ring of width kStrokeWidth instead
  std::string mesh_path;  ///< Shape::Mesh: the file it was read from
  std::shared_ptr<const TriangleMesh> mesh;  ///< Shape::Mesh: placed as modelled

  /// @brief The spec this primitive parses from: "sphere", "circle-outline", "mesh:leaf.ply".
  std::string name() const;
  /// @brief A shape of the plane (line, circle, triangle, square).
  bool flat() const { return shape == Shape::Line || shape == Shape::Circle || shape == Shape::Triangle || shape == Shape::Square; }
  /// @brief Radius of the ball around the frame origin holding the shape, in units of d.
  double bounding_radius() const;
};

/// @brief Names of the built-in primitives.
const std::vector<std::string>& builtin_primitive_names();

/// @brief The primitive tessellated in its frame, with normals: flat shapes face +z; curved
/// ones have about `segments` segments around. User meshes come back as read.
TriangleMesh primitive_mesh(const Primitive& primitive, int segments = 32);

}  // namespace ifsforge
