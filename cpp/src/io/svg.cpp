// SVG of 2D instance lists.
#include "ifsforge/io/svg.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/io/atomic_file.h"
#include "ifsforge/io/pov_text.h"

namespace ifsforge {
namespace {

using Vec2 = std::array<double, 2>;

void number(std::string& out, double v) {
  char buffer[40];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, std::isfinite(v) ? v : 0.0, std::chars_format::fixed, 2);
  out.append(buffer, r.ptr);
}

std::string hex_color(const std::array<float, 4>& c) {
  static const char digits[] = "0123456789abcdef";
  std::string out = "#";
  for (int k = 0; k < 3; ++k) {
    const int v = static_cast<int>(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
    out += digits[v >> 4];
    out += digits[v & 15];
  }
  return out;
}

/// Andrew's monotone chain: the convex hull, counter-clockwise.
std::vector<Vec2> convex_hull(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end());
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  auto turn = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  };
  std::vector<Vec2> hull(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && turn(hull[k - 2], hull[k - 1], p[i - 1]) <= 0) --k;
    hull[k++] = p[i - 1];
  }
  hull.resize(k - 1);
  return hull;
}

/// The local outline (in units of d, frame coordinates) of a polygonal primitive.
std::vector<Vec2> local_polygon(const Primitive& p) {
  const double t = 1.0 / std::sqrt(3.0), c = 1.0 / std::sqrt(2.0), h = std::sqrt(3.0) / 2.0;
  switch (p.shape) {
    case Shape::Triangle: return {{0, 0}, {1, 0}, {0.5, h}};  // Eq. 95
    case Shape::Square: return {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    case Shape::Box: return {{-t, -t}, {t, -t}, {t, t}, {-t, t}};
    case Shape::Cylinder: return {{-c, -c}, {c, -c}, {c, c}, {-c, c}};
    case Shape::Cone: return {{1, 0}, {-0.5, h}, {-0.5, -h}};
    case Shape::Mesh: {
      std::vector<Vec2> points;
      for (const auto& v : p.mesh->positions) points.push_back({v[0], v[1]});
      return convex_hull(points);
    }
    default: return {};
  }
}

}  // namespace

void write_svg(const std::string& path, const InstanceList& list, const SvgOptions& options) {
  if (list.spatial_dims != 2)
    throw InputError("SVG shows 2D instance lists; this one is 3D (use the POV-Ray or glTF export, or draw_instances)");
  if (options.width < 1 || options.width > 65535) throw InputError("the SVG width must be 1..65535 pixels");
  if (!(options.margin >= 0.0 && options.margin < 0.45)) throw InputError("the margin must be in [0, 0.45)");
  check_writable(path);
  std::array<double, 3> lo, hi;
  if (!list.bounds(lo, hi)) throw InputError("no instance has a positive scale: nothing to draw");
  const double span = std::max({hi[0] - lo[0], hi[1] - lo[1], 1e-12});
  const double pad = options.margin * span;
  const double xmin = lo[0] - pad, ymax = hi[1] + pad;
  const double scale = options.width / (hi[0] - lo[0] + 2.0 * pad > 0 ? hi[0] - lo[0] + 2.0 * pad : 1.0);
  const int height = std::max(1, static_cast<int>(std::ceil((hi[1] - lo[1] + 2.0 * pad) * scale)));

  std::vector<std::vector<Vec2>> polygons;
  for (const auto& p : list.primitives) polygons.push_back(local_polygon(p));

  AtomicFile file(path);
  std::string out;
  out += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" + std::to_string(options.width) +
         "\" height=\"" + std::to_string(height) + "\" viewBox=\"0 0 " + std::to_string(options.width) + " " +
         std::to_string(height) + "\">\n";
  out += "<title>" + xml_text(options.title.empty() ? list.name : options.title) + "</title>\n";
  out += "<desc>Vector IFS instances (seed 5.8.2, 6.1.3.5) written by ifsforge</desc>\n";
  if (options.background) {
    const auto& b = *options.background;
    out += "<rect width=\"100%\" height=\"100%\" fill=\"" + hex_color({b[0], b[1], b[2], 1.0f}) + "\"/>\n";
  }
  out += "<g>\n";
  auto to_svg = [&](double x, double y, std::string& s) {
    number(s, (x - xmin) * scale);
    s += ',';
    number(s, (ymax - y) * scale);
  };
  for (std::size_t i = 0; i < list.size(); ++i) {
    const float d = list.scales[i];
    if (!(d > 0.0f) || !std::isfinite(d)) continue;
    const Primitive& prim = list.primitives[list.primitive[i]];
    const auto& pos = list.positions[i];
    const auto& f = list.frames[i];
    auto world = [&](double lx, double ly) -> Vec2 {
      return {pos[0] + d * (lx * f[0] + ly * f[3]), pos[1] + d * (lx * f[1] + ly * f[4])};
    };
    const std::string color = hex_color(list.colors[i]);
    std::string paint;
    auto fill = [&]() {
      paint = " fill=\"" + color + "\"";
      if (list.colors[i][3] < 0.9995f) {
        paint += " fill-opacity=\"";
        number(paint, list.colors[i][3]);
        paint += "\"";
      }
    };
    auto stroke = [&](double width) {
      paint = " fill=\"none\" stroke=\"" + color + "\" stroke-width=\"";
      number(paint, width * scale);
      paint += "\"";
      if (list.colors[i][3] < 0.9995f) {
        paint += " stroke-opacity=\"";
        number(paint, list.colors[i][3]);
        paint += "\"";
      }
    };
    switch (prim.shape) {
      case Shape::Line: {
        const Vec2 a = world(0, 0), b = world(1, 0);  // Eq. 62: q0 -> qh
        stroke(kStrokeWidth * d);
        out += "<line x1=\"";
        number(out, (a[0] - xmin) * scale);
        out += "\" y1=\"";
        number(out, (ymax - a[1]) * scale);
        out += "\" x2=\"";
        number(out, (b[0] - xmin) * scale);
        out += "\" y2=\"";
        number(out, (ymax - b[1]) * scale);
        out += "\"" + paint + "/>\n";
        break;
      }
      case Shape::Circle:
      case Shape::Sphere:
      case Shape::Torus: {
        double r = d;
        if (prim.shape == Shape::Torus) {
          r = 0.75 * d;
          stroke(0.5 * d);
        } else if (prim.outline) {
          stroke(kStrokeWidth * d);
        } else {
          fill();
        }
        out += "<circle cx=\"";
        number(out, (pos[0] - xmin) * scale);
        out += "\" cy=\"";
        number(out, (ymax - pos[1]) * scale);
        out += "\" r=\"";
        number(out, r * scale);
        out += "\"" + paint + "/>\n";
        break;
      }
      default: {
        const auto& poly = polygons[list.primitive[i]];
        if (poly.size() < 3) break;
        if (prim.outline) {
          stroke(kStrokeWidth * d);
          paint += " stroke-linejoin=\"miter\"";
        } else {
          fill();
        }
        out += "<polygon points=\"";
        for (std::size_t k = 0; k < poly.size(); ++k) {
          if (k) out += ' ';
          const Vec2 w = world(poly[k][0], poly[k][1]);
          to_svg(w[0], w[1], out);
        }
        out += "\"" + paint + "/>\n";
      }
    }
    if (out.size() > (1u << 20)) {
      write_bytes(file.file(), out.data(), out.size(), path);
      out.clear();
    }
  }
  out += "</g>\n</svg>\n";
  write_bytes(file.file(), out.data(), out.size(), path);
  file.commit();
}

}  // namespace ifsforge
