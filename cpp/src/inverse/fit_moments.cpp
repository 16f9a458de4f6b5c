#include "fit_moments.h"

#include <algorithm>
#include <cmath>

#include "fit_shared.h"

namespace ifsforge {

double Moments::axis() const { return 0.5 * std::atan2(2 * xy, xx - yy); }

Moments moments_of(const std::vector<std::array<double, 2>>& points) {
  Moments m;
  if (points.empty()) return m;
  for (const auto& p : points) m.centroid[0] += p[0], m.centroid[1] += p[1];
  m.centroid[0] /= points.size(), m.centroid[1] /= points.size();
  for (const auto& p : points) {
    const double dx = p[0] - m.centroid[0], dy = p[1] - m.centroid[1];
    m.xx += dx * dx, m.xy += dx * dy, m.yy += dy * dy;
  }
  m.xx /= points.size(), m.xy /= points.size(), m.yy /= points.size();
  return m;
}

std::vector<std::array<double, 6>> moment_maps(const Moments& whole, const Moments& piece, double max_contraction,
                                               int turns) {
  std::vector<std::array<double, 6>> out;
  if (!(whole.spread() > 0)) return out;
  const double s = std::clamp(std::sqrt(piece.spread() / whole.spread()), 0.05, max_contraction);
  // The turn that lays the whole's axis on the piece's is their difference unmirrored and their
  // sum mirrored; the axes are undirected, so each also half a turn on. Trying both turns with
  // and without the mirror covers either convention of the mirror in Eq. 5. A round ellipse
  // has no axis to speak of: the `turns` angles over the full circle stand in for it.
  std::vector<double> angles;
  for (double base : {piece.axis() - whole.axis(), piece.axis() + whole.axis()})
    for (double half : {0.0, M_PI}) angles.push_back(base + half);
  for (int k = 0; k < turns; ++k) angles.push_back(k * 2 * M_PI / turns);
  for (int mirror = 0; mirror < 2; ++mirror)
    for (double angle : angles) {
        std::array<double, 6> p = {mirror ? -s : s, s, angle, angle, 0, 0};
        AffineMap m;
        decode_map(p.data(), 2, max_contraction, m);
        p[4] = piece.centroid[0] - (m.a(0, 0) * whole.centroid[0] + m.a(0, 1) * whole.centroid[1]);
        p[5] = piece.centroid[1] - (m.a(1, 0) * whole.centroid[0] + m.a(1, 1) * whole.centroid[1]);
        out.push_back(p);
      }
  return out;
}

namespace {

/// The square root of a covariance {xx, xy, yy}: (M + sqrt(det M) I) / sqrt(tr M + 2 sqrt(det M)),
/// a flat ellipse's determinant held above zero.
std::array<double, 3> covariance_root(const Moments& m) {
  const double r = std::sqrt(std::max(m.xx * m.yy - m.xy * m.xy, 1e-18)), t = std::sqrt(m.spread() + 2 * r);
  return {(m.xx + r) / t, m.xy / t, (m.yy + r) / t};
}

}  // namespace

std::array<double, 6> ellipse_map(const Moments& whole, const Moments& piece, double angle, bool mirror) {
  const auto p = covariance_root(piece), w = covariance_root(whole);
  const double det = w[0] * w[2] - w[1] * w[1];
  const double wi[2][2] = {{w[2] / det, -w[1] / det}, {-w[1] / det, w[0] / det}};  // W^(-1/2)
  const double f = mirror ? -1 : 1, c = std::cos(angle), s = std::sin(angle);
  const double pq[2][2] = {{p[0] * c * f + p[1] * s * f, -p[0] * s + p[1] * c},  // P^(1/2) R(angle) F
                           {p[1] * c * f + p[2] * s * f, -p[1] * s + p[2] * c}};
  double a[2][2];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) a[i][j] = pq[i][0] * wi[0][j] + pq[i][1] * wi[1][j];
  // Eq. 5's parameters: column 0 is Mx (cos theta_x, sin theta_x), column 1 My (-sin theta_y, cos theta_y).
  return {std::hypot(a[0][0], a[1][0]), std::hypot(a[0][1], a[1][1]), std::atan2(a[1][0], a[0][0]),
          std::atan2(-a[0][1], a[1][1]),
          piece.centroid[0] - (a[0][0] * whole.centroid[0] + a[0][1] * whole.centroid[1]),
          piece.centroid[1] - (a[1][0] * whole.centroid[0] + a[1][1] * whole.centroid[1])};
}

std::vector<std::array<double, 6>> symmetric_copies(const std::vector<double>& x0, const Moments& whole) {
  const auto& c = whole.centroid;
  std::vector<std::array<double, 6>> out;
  for (std::size_t i = 0; i + 6 <= x0.size(); i += 6) {
    const double s = x0[i + 1], turn = x0[i + 2], bx = x0[i + 4] - c[0], by = x0[i + 5] - c[1];
    const bool mirror = x0[i] < 0;
    // Reflection S in the line at angle a: S R(t) F^m = R(2a - t + pi) F^(1-m) (Eq. 5's A = R F).
    for (double a : {whole.axis(), whole.axis() + M_PI / 2}) {
      const double ca = std::cos(2 * a), sa = std::sin(2 * a), t = 2 * a - turn + M_PI;
      out.push_back({mirror ? s : -s, s, t, t, c[0] + ca * bx + sa * by, c[1] + sa * bx - ca * by});
    }
    out.push_back({x0[i], s, turn + M_PI, turn + M_PI, c[0] - bx, c[1] - by});
  }
  return out;
}

std::vector<std::uint8_t> grow_cells(const std::vector<std::uint8_t>& mask, int w, int h) {
  std::vector<std::uint8_t> out = mask;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x)
      for (int dy = -1; dy <= 1 && !out[std::size_t(y) * w + x]; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (mask[std::size_t(y + dy) * w + x + dx]) {
            out[std::size_t(y) * w + x] = 1;
            break;
          }
  return out;
}

std::vector<std::vector<std::size_t>> mask_parts(const std::vector<std::uint8_t>& grown,
                                                 const std::vector<std::uint8_t>& on, int w, int h, std::size_t most) {
  std::vector<int> label(grown.size(), -1);
  std::vector<std::vector<std::size_t>> parts;
  std::vector<std::size_t> stack;
  for (std::size_t start = 0; start < grown.size(); ++start) {
    if (!grown[start] || label[start] >= 0) continue;
    const int id = int(parts.size());
    parts.emplace_back();
    label[start] = id;
    stack.assign(1, start);
    while (!stack.empty()) {
      const std::size_t q = stack.back();
      stack.pop_back();
      if (on[q]) parts.back().push_back(q);
      const int x = int(q % w), y = int(q / w);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const std::size_t n = std::size_t(ny) * w + nx;
          if (grown[n] && label[n] < 0) label[n] = id, stack.push_back(n);
        }
    }
  }
  if (parts.size() < 2) return {};
  // Largest first, ties in scan order: the same parts whatever the thread count.
  std::stable_sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  if (parts.size() > most) parts.resize(most);
  return parts;
}

}  // namespace ifsforge
