#include "ifsforge/vector/draw.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {
namespace {

using Vec3 = std::array<double, 3>;

constexpr int kBandRows = 16;                    // pixel rows per job
constexpr int kLevelSegments[3] = {8, 16, 32};   // tessellations by projected size

struct Projection {
  Vec3 u{1, 0, 0}, v{0, 1, 0}, d{0, 0, -1};  // image axes and viewing direction (2D: from above)
  double xmin = 0, ymax = 0, scale = 1;       // image plane -> samples
};

int level_of(double radius_samples) { return radius_samples < 6.0 ? 0 : radius_samples < 24.0 ? 1 : 2; }

}  // namespace

Image draw_instances(const InstanceList& list, const DrawOptions& options) {
  check_image_size(options.width, options.height);
  if (options.supersample < 1 || options.supersample > 8) throw InputError("supersampling must be 1..8 per axis");
  const int w = options.width, h = options.height, ss = options.supersample;
  check_memory(double(w) * h * 16.0 + list.size() * 24.0, "a " + std::to_string(w) + "x" + std::to_string(h) + " instance drawing");

  Projection proj;
  if (list.spatial_dims == 3) {
    const double yaw = options.view.yaw * M_PI / 180.0, pitch = options.view.pitch * M_PI / 180.0;
    proj.u = {std::cos(yaw), std::sin(yaw), 0.0};
    proj.v = {-std::sin(pitch) * std::sin(yaw), std::sin(pitch) * std::cos(yaw), std::cos(pitch)};
    // The viewing direction v x u (away from Frame::toward_viewer).
    proj.d = {proj.v[1] * proj.u[2] - proj.v[2] * proj.u[1], proj.v[2] * proj.u[0] - proj.v[0] * proj.u[2],
              proj.v[0] * proj.u[1] - proj.v[1] * proj.u[0]};
  }
  auto dot = [](const Vec3& a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  std::vector<double> radius(list.primitives.size());
  for (std::size_t p = 0; p < list.primitives.size(); ++p) radius[p] = list.primitives[p].bounding_radius();

  // The window: given, or the projected bounding balls, stretched to the aspect ratio.
  Window window;
  if (options.window) {
    window = *options.window;
  } else {
    double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!(list.scales[i] > 0.0f)) continue;
      const double r = list.scales[i] * radius[list.primitive[i]];
      const double pu = dot(proj.u, list.positions[i].data()), pv = dot(proj.v, list.positions[i].data());
      u0 = std::min(u0, pu - r);
      u1 = std::max(u1, pu + r);
      v0 = std::min(v0, pv - r);
      v1 = std::max(v1, pv + r);
    }
    if (!(u1 >= u0)) throw InputError("no instance has a positive scale: nothing to draw");
    double cw = std::max(u1 - u0, 1e-12), ch = std::max(v1 - v0, 1e-12);
    const double aspect = static_cast<double>(w) / h;
    if (cw / ch < aspect) cw = ch * aspect; else ch = cw / aspect;
    cw *= 1.06;
    ch *= 1.06;
    window = {0.5 * (u0 + u1) - 0.5 * cw, 0.5 * (v0 + v1) - 0.5 * ch, 0.5 * (u0 + u1) + 0.5 * cw, 0.5 * (v0 + v1) + 0.5 * ch};
  }
  if (!(window.xmax > window.xmin && window.ymax > window.ymin)) throw InputError("the window is empty");
  proj.xmin = window.xmin;
  proj.ymax = window.ymax;
  const double sx = w * ss / (window.xmax - window.xmin), sy = h * ss / (window.ymax - window.ymin);

  // Paint order: list order in 2D; far to near along the view in 3D (stable: ties keep order).
  std::vector<std::uint32_t> order;
  for (std::size_t i = 0; i < list.size(); ++i)
    if (list.scales[i] > 0.0f && std::isfinite(list.scales[i])) order.push_back(static_cast<std::uint32_t>(i));
  if (list.spatial_dims == 3)
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return dot(proj.d, list.positions[a].data()) > dot(proj.d, list.positions[b].data());
    });

  // Which bands each instance touches, by its projected bounding ball.
  const int bands = (h + kBandRows - 1) / kBandRows;
  std::vector<std::vector<std::uint32_t>> in_band(bands);
  std::vector<float> sample_radius(list.size(), 0.0f);
  for (std::uint32_t i : order) {
    const double r = list.scales[i] * radius[list.primitive[i]];
    const double pv = dot(proj.v, list.positions[i].data());
    sample_radius[i] = static_cast<float>(r * std::max(sx, sy));
    const double top = (proj.ymax - (pv + r)) * sy / ss, bottom = (proj.ymax - (pv - r)) * sy / ss;
    if (bottom < 0 || top >= h) continue;
    const int b0 = std::max(0, static_cast<int>(top) / kBandRows), b1 = std::min(bands - 1, static_cast<int>(bottom) / kBandRows);
    for (int b = b0; b <= b1; ++b) in_band[b].push_back(i);
  }

  std::vector<std::array<TriangleMesh, 3>> meshes(list.primitives.size());
  for (std::size_t p = 0; p < list.primitives.size(); ++p)
    for (int level = 0; level < 3; ++level) meshes[p][level] = primitive_mesh(list.primitives[p], kLevelSegments[level]);
  // The key light of the POV-Ray scenes: above left, behind the viewer.
  Vec3 light{-proj.d[0] + 0.6 * proj.v[0] - 0.5 * proj.u[0], -proj.d[1] + 0.6 * proj.v[1] - 0.5 * proj.u[1],
             -proj.d[2] + 0.6 * proj.v[2] - 0.5 * proj.u[2]};
  const double ll = std::sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
  for (double& c : light) c /= ll;

  Image image(w, h, 4);
  const auto& bg = options.background;
  parallel_jobs(bands, options.threads, [&](std::size_t band, int) {
    const int row0 = static_cast<int>(band) * kBandRows, rows = std::min(kBandRows, h - row0);
    const int sw = w * ss, sh = rows * ss, sy0 = row0 * ss;
    // Premultiplied RGBA samples.
    std::vector<float> samples(std::size_t(sw) * sh * 4);
    for (std::size_t s = 0; s < samples.size(); s += 4) {
      samples[s] = bg[0] * bg[3];
      samples[s + 1] = bg[1] * bg[3];
      samples[s + 2] = bg[2] * bg[3];
      samples[s + 3] = bg[3];
    }
    std::vector<std::array<double, 2>> screen;
    std::vector<Vec3> world;
    for (std::uint32_t i : in_band[band]) {
      const Primitive& prim = list.primitives[list.primitive[i]];
      const TriangleMesh& mesh = meshes[list.primitive[i]][level_of(sample_radius[i])];
      const auto& pos = list.positions[i];
      const auto& f = list.frames[i];
      const double d = list.scales[i];
      world.resize(mesh.positions.size());
      screen.resize(mesh.positions.size());
      for (std::size_t k = 0; k < mesh.positions.size(); ++k) {
        const auto& l = mesh.positions[k];
        Vec3& p = world[k];
        for (int c = 0; c < 3; ++c) p[c] = pos[c] + d * (l[0] * f[c] + l[1] * f[3 + c] + l[2] * f[6 + c]);
        const double pu = proj.u[0] * p[0] + proj.u[1] * p[1] + proj.u[2] * p[2];
        const double pv = proj.v[0] * p[0] + proj.v[1] * p[1] + proj.v[2] * p[2];
        screen[k] = {(pu - proj.xmin) * sx, (proj.ymax - pv) * sy - sy0};
      }
      const auto& color = list.colors[i];
      const bool flat = prim.flat() || list.spatial_dims == 2;
      for (const auto& t : mesh.triangles) {
        float shade = 1.0f;
        if (!flat) {
          const Vec3& a = world[t[0]];
          const Vec3& b = world[t[1]];
          const Vec3& c = world[t[2]];
          const Vec3 e1{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
          Vec3 n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
          if (n[0] * proj.d[0] + n[1] * proj.d[1] + n[2] * proj.d[2] >= 0.0) continue;  // faces away
          const double nl = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
          const double lambert = nl > 0 ? (n[0] * light[0] + n[1] * light[1] + n[2] * light[2]) / nl : 0.0;
          shade = static_cast<float>(0.3 + 0.7 * std::max(0.0, lambert));
        }
        const auto& a = screen[t[0]];
        const auto& b = screen[t[1]];
        const auto& c = screen[t[2]];
        const double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if (area == 0.0) continue;
        const double sign = area > 0 ? 1.0 : -1.0;
        const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a[0], b[0], c[0]}))));
        const int x1 = std::min(sw - 1, static_cast<int>(std::ceil(std::max({a[0], b[0], c[0]}))));
        const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a[1], b[1], c[1]}))));
        const int y1 = std::min(sh - 1, static_cast<int>(std::ceil(std::max({a[1], b[1], c[1]}))));
        const float alpha = color[3];
        const float r = color[0] * shade * alpha, g = color[1] * shade * alpha, bl = color[2] * shade * alpha;
        for (int y = y0; y <= y1; ++y) {
          const double py = y + 0.5;
          for (int x = x0; x <= x1; ++x) {
            const double px = x + 0.5;
            const double w0 = sign * ((b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]));
            const double w1 = sign * ((c[0] - b[0]) * (py - b[1]) - (c[1] - b[1]) * (px - b[0]));
            const double w2 = sign * ((a[0] - c[0]) * (py - c[1]) - (a[1] - c[1]) * (px - c[0]));
            if (w0 < 0 || w1 < 0 || w2 < 0) continue;
            float* s = &samples[(std::size_t(y) * sw + x) * 4];
            s[0] = r + s[0] * (1.0f - alpha);
            s[1] = g + s[1] * (1.0f - alpha);
            s[2] = bl + s[2] * (1.0f - alpha);
            s[3] = alpha + s[3] * (1.0f - alpha);
          }
        }
      }
    }
    // Box filter down to pixels; un-premultiply.
    const float weight = 1.0f / (ss * ss);
    for (int y = 0; y < rows; ++y)
      for (int x = 0; x < w; ++x) {
        float sum[4] = {0, 0, 0, 0};
        for (int j = 0; j < ss; ++j)
          for (int i = 0; i < ss; ++i) {
            const float* s = &samples[(std::size_t(y * ss + j) * sw + x * ss + i) * 4];
            for (int c = 0; c < 4; ++c) sum[c] += s[c];
          }
        const float a = sum[3] * weight;
        for (int c = 0; c < 3; ++c) image.at(x, row0 + y, c) = a > 0 ? std::clamp(sum[c] * weight / a, 0.0f, 1.0f) : 0.0f;
        image.at(x, row0 + y, 3) = a;
      }
  });
  return image;
}

}  // namespace ifsforge
