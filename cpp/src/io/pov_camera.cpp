// Cameras, lights and floors framed for POV-Ray scenes (io/pov_camera.h).
#include <algorithm>
#include <cmath>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/io/pov_camera.h"

namespace ifsforge {
namespace {

PovVector operator+(const PovVector& a, const PovVector& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
PovVector operator-(const PovVector& a, const PovVector& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
PovVector operator*(double s, const PovVector& a) { return {s * a[0], s * a[1], s * a[2]}; }
double dot(const PovVector& a, const PovVector& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
PovVector cross(const PovVector& a, const PovVector& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
PovVector unit(const PovVector& a) { return (1.0 / std::sqrt(dot(a, a))) * a; }

}  // namespace

PovFraming frame_balls(const std::vector<PovBall>& balls, const PovView& view, int width, int height) {
  if (balls.empty()) throw InputError("nothing to frame");
  if (width < 1 || height < 1) throw InputError("the image size must be positive");
  if (!(view.margin >= 0.0 && view.margin < 0.45)) throw InputError("the margin must be in [0, 0.45)");
  if (!view.orthographic && !(view.fov > 1.0 && view.fov < 170.0))
    throw InputError("the field of view must be between 1 and 170 degrees");
  PovVector lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const PovBall& b : balls) {
    if (!std::isfinite(b.radius) || b.radius < 0.0) throw InputError("cannot frame a ball with a bad radius");
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(b.centre[c])) throw InputError("cannot frame an infinite point");
      lo[c] = std::min(lo[c], b.centre[c] - b.radius);
      hi[c] = std::max(hi[c], b.centre[c] + b.radius);
    }
  }
  PovFraming f;
  f.centre = 0.5 * (lo + hi);
  f.radius = 0.5 * std::sqrt(dot(hi - lo, hi - lo));
  const double size = f.radius > 0.0 ? f.radius : 1.0;
  // Frame's image-plane axes (render/frame.h); the camera looks along v x u, away from the
  // viewer of Frame::toward_viewer, so right-handed coordinates show unmirrored.
  const double yaw = view.yaw * M_PI / 180.0, pitch = view.pitch * M_PI / 180.0;
  const PovVector u{std::cos(yaw), std::sin(yaw), 0.0};
  const PovVector v{-std::sin(pitch) * std::sin(yaw), std::sin(pitch) * std::cos(yaw), std::cos(pitch)};
  const PovVector d = cross(v, u);
  f.camera.sky = v;
  const double aspect = static_cast<double>(width) / height;
  double distance;
  PovCamera& cam = f.camera;
  cam.orthographic = view.orthographic;
  if (view.orthographic) {
    double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (const PovBall& b : balls) {
      const PovVector r = b.centre - f.centre;
      u0 = std::min(u0, dot(r, u) - b.radius);
      u1 = std::max(u1, dot(r, u) + b.radius);
      v0 = std::min(v0, dot(r, v) - b.radius);
      v1 = std::max(v1, dot(r, v) + b.radius);
    }
    double w = std::max(u1 - u0, 1e-9 * size), h = std::max(v1 - v0, 1e-9 * size);
    if (w / h < aspect) w = h * aspect; else h = w / aspect;
    w /= 1.0 - 2.0 * view.margin;
    h /= 1.0 - 2.0 * view.margin;
    distance = 2.0 * size;
    const PovVector aim = f.centre + (0.5 * (u0 + u1)) * u + (0.5 * (v0 + v1)) * v;
    cam.location = aim - distance * d;
    cam.look_at = aim;
    cam.direction = d;
    cam.right = w * u;
    cam.up = h * v;
  } else {
    // A ball at (x, depth z) from the camera shows whole in a half-angle t when
    // x cos t - z sin t <= -r, i.e. the camera sits at least x / tan t + r / sin t - z back.
    const double tan_h = std::tan(0.5 * view.fov * M_PI / 180.0) * (1.0 - 2.0 * view.margin);
    const double tan_v = tan_h / aspect;
    const double sec_h = std::sqrt(1.0 + 1.0 / (tan_h * tan_h)), sec_v = std::sqrt(1.0 + 1.0 / (tan_v * tan_v));
    distance = 1.05 * size;
    for (const PovBall& b : balls) {
      const PovVector r = b.centre - f.centre;
      distance = std::max(distance, std::abs(dot(r, u)) / tan_h + b.radius * sec_h - dot(r, d));
      distance = std::max(distance, std::abs(dot(r, v)) / tan_v + b.radius * sec_v - dot(r, d));
    }
    cam.location = f.centre - distance * d;
    cam.look_at = f.centre;
    cam.direction = (aspect / (2.0 * std::tan(0.5 * view.fov * M_PI / 180.0))) * d;
    cam.right = aspect * u;
    cam.up = v;
  }
  const double light = 2.0 * (distance + 2.0 * size);
  f.key_light = f.centre + light * unit(-1.0 * d + 0.6 * v - 0.5 * u);
  f.fill_light = f.centre + light * unit(-0.8 * d + 0.2 * v + 0.7 * u);
  // The floor goes on the far side of the box from the camera along z.
  f.floor_height = d[2] > 0.05 ? hi[2] + 0.01 * size : lo[2] - 1e-4 * size;
  return f;
}

}  // namespace ifsforge
