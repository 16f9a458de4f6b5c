// Point recursive rendering (5.8.1) of systems with polar maps (3.3.3).
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>

#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/parameters.h"
#include "polar_render.h"

namespace ifsforge::polar {
namespace {

// The stopping rule. A polar map is only locally contractive (Eq. 30): |P w(M)| <= s |P M|
// bounds how far an image lies from P, not its diameter, so the size of a piece w_u(A) is
// estimated, not bounded: by the images of kSamples points S_k of A (the start point, the
// sample's extremes in 8 directions and 7 more of its points) while the piece is wide, then by
// its linearisation q + J (S_k - S_0) once it is under kLinearBelow pixels (J fitted to those
// images by least squares, then carried by each map's Jacobian at q: 3 map evaluations a
// node instead of kSamples). A piece stops once the estimate is under `cut` pixels and plots
// its kSamples estimated points, each with 1/kSamples of its mass; also once its mass is under
// 1 / (kLeavesPerPixel H V): random iteration's Eq. 44-45 counts give such a piece a few points
// at most, and without this cut heavily overlapping systems (sum s_i^2 > 1) split into far
// more pieces than pixels. Depth kMaxDepth and a job-local node budget end the rest (neither
// depends on the threads).
constexpr int kSamples = 16;
constexpr double kLinearBelow = 4.0;
constexpr int kMaxDepth = 60;
constexpr std::uint64_t kJobsWanted = 256;
constexpr double kLeavesPerPixel = 4.0;

using Mat = std::array<double, 4>;  // row-major 2 x 2

/// One piece w_u(A) of the recursion.
struct Piece {
  Point q{};                                // the image of S_0 (exact: the maps themselves)
  std::array<Point, kSamples> images;       // wide: the images of every S_k
  Mat J{};                                  // linear: the piece is about q + J (S_k - S_0)
  bool linear = false;
  double mass = 1.0;                        // product of the probabilities along u

  Point point(int k, const std::array<std::array<double, 2>, kSamples>& d) const {
    if (!linear) return images[k];
    Point p = q;
    p[0] += J[0] * d[k][0] + J[1] * d[k][1];
    p[1] += J[2] * d[k][0] + J[3] * d[k][1];
    return p;
  }
};

struct Setup {
  const Ifs& ifs;
  Frame frame;
  std::array<Point, kSamples> samples;
  std::array<std::array<double, 2>, kSamples> d{};  // S_k - S_0
  Mat gram_inverse{};                              // (sum_k d_k d_k^T)^-1
  double h = 0.0;                                  // finite-difference step of the Jacobians
  int depth = 0, prefix = 0;
  std::uint64_t jobs = 1, budget = 0;
  double cut = 1.0, min_mass = 0.0;
  std::vector<double> lo, hi;

  Setup(const Ifs& system, const RenderOptions& options, const Renderer& renderer)
      : ifs(system), frame(Frame::fit(system, options.width, options.height, options.window, options.view)) {
    ifs.require_attractor();
    const ParameterValues values(renderer, options);
    cut = values.automatic("cut") ? (options.binary ? 0.5 : 1.0) : values.number("cut", 1.0 / 64.0, 1.0);
    depth = std::max(options.depth, 0);
    std::vector<Point> sample;
    sample_attractor(ifs, 4096, 0x9A1A5, [&](const Point& p) { sample.push_back(p); });
    samples[0] = ifs.start_point();
    for (int j = 0; j < 8; ++j) {
      const double cx = std::cos(j * M_PI / 4), cy = std::sin(j * M_PI / 4);
      samples[1 + j] = *std::max_element(sample.begin(), sample.end(), [&](const Point& a, const Point& b) {
        return a[0] * cx + a[1] * cy < b[0] * cx + b[1] * cy;
      });
    }
    for (int j = 0; j < 7; ++j) samples[9 + j] = sample[(j + 1) * sample.size() / 8];
    double g[4] = {0, 0, 0, 0}, extent = 0.0;
    for (int k = 0; k < kSamples; ++k) {
      d[k] = {samples[k][0] - samples[0][0], samples[k][1] - samples[0][1]};
      g[0] += d[k][0] * d[k][0];
      g[1] += d[k][0] * d[k][1];
      g[3] += d[k][1] * d[k][1];
      extent = std::max({extent, std::abs(d[k][0]), std::abs(d[k][1])});
    }
    // A ridge keeps a straight attractor (a singular Gram matrix) solvable.
    const double ridge = 1e-9 * (g[0] + g[3]) + 1e-300;
    g[0] += ridge;
    g[3] += ridge;
    const double det = g[0] * g[3] - g[1] * g[1];
    gram_inverse = {g[3] / det, -g[1] / det, -g[1] / det, g[0] / det};
    h = std::max(extent, 1e-300) * 1e-7;
    const std::size_t n = ifs.size();
    if (n > 1)
      for (prefix = 0; jobs < kJobsWanted && prefix < 12; ++prefix) jobs *= n;
    if (depth > 0 && prefix > depth) {
      prefix = depth;
      jobs = 1;
      for (int l = 0; l < prefix; ++l) jobs *= n;
    }
    const std::uint64_t total =
        std::max<std::uint64_t>(std::uint64_t(1) << 24, 128 * std::uint64_t(frame.width()) * frame.height());
    budget = std::max<std::uint64_t>(4096, total / jobs);
    min_mass = 1.0 / (kLeavesPerPixel * frame.width() * frame.height());
    channel_ranges(ifs, lo, hi);
  }

  Accumulator empty() const { return Accumulator(frame.width(), frame.height(), true, lo, hi); }

  void child(const Piece& piece, std::size_t i, Piece& out) const {
    out.mass = piece.mass * ifs.probabilities()[i];
    out.q = ifs.apply(i, piece.q);
    out.linear = piece.linear || depth > 0;  // a fixed depth carries q alone
    if (depth > 0) return;
    if (!piece.linear) {
      for (int k = 0; k < kSamples; ++k) out.images[k] = ifs.apply(i, piece.images[k]);
      return;
    }
    // out.J = Dw_i(q) piece.J, the Jacobian by forward differences.
    Point a = piece.q, b = piece.q;
    a[0] += h;
    b[1] += h;
    a = ifs.apply(i, a);
    b = ifs.apply(i, b);
    const Mat D = {(a[0] - out.q[0]) / h, (b[0] - out.q[0]) / h, (a[1] - out.q[1]) / h, (b[1] - out.q[1]) / h};
    const Mat& J = piece.J;
    out.J = {D[0] * J[0] + D[1] * J[2], D[0] * J[1] + D[1] * J[3], D[2] * J[0] + D[3] * J[2],
             D[2] * J[1] + D[3] * J[3]};
  }

  /// J of a wide piece: least squares of (image_k - image_0) = J d_k.
  void linearise(Piece& piece) const {
    double e[4] = {0, 0, 0, 0};
    for (int k = 1; k < kSamples; ++k) {
      const double ex = piece.images[k][0] - piece.images[0][0], ey = piece.images[k][1] - piece.images[0][1];
      e[0] += ex * d[k][0];
      e[1] += ex * d[k][1];
      e[2] += ey * d[k][0];
      e[3] += ey * d[k][1];
    }
    const Mat& g = gram_inverse;
    piece.J = {e[0] * g[0] + e[1] * g[2], e[0] * g[1] + e[1] * g[3], e[2] * g[0] + e[3] * g[2],
               e[2] * g[1] + e[3] * g[3]};
    piece.linear = true;
  }

  void plot(const Point& p, const Point& channels, double mass, Accumulator& acc) const {
    const auto px = frame.to_pixel(p);
    const bool inside = px[0] >= 0.0 && px[0] < frame.width() && px[1] >= 0.0 && px[1] < frame.height();
    const std::size_t pixel = inside ? std::size_t(px[1]) * frame.width() + std::size_t(px[0])
                                     : std::size_t(frame.width()) * frame.height();
    acc.add(pixel, ifs.dim() > 2 ? channels.data() + 2 : nullptr, mass);
  }

  void leaf(const Piece& piece, Accumulator& acc) const {
    if (depth > 0) return plot(piece.q, piece.q, piece.mass, acc);  // the seed's PRR(q, L)
    for (int k = 0; k < kSamples; ++k) plot(piece.point(k, d), piece.linear ? piece.q : piece.images[k], piece.mass / kSamples, acc);
  }

  struct Walk {
    std::vector<Piece> level;
    std::vector<std::uint32_t> digits;  // the job's address prefix
    std::uint64_t nodes = 0, leaves = 0;
    Accumulator* acc;
  };

  void descend(Walk& w, int at) const {
    const std::size_t n = ifs.size();
    const double width = frame.width(), height = frame.height();
    for (std::size_t i = at < prefix ? w.digits[at] : 0; i < (at < prefix ? w.digits[at] + 1 : n); ++i) {
      Piece& piece = w.level[at + 1];
      child(w.level[at], i, piece);
      ++w.nodes;
      const bool in_prefix = at + 1 < prefix;
      if (depth > 0) {
        if (at + 1 == depth) {
          leaf(piece, *w.acc);
          ++w.leaves;
        } else {
          descend(w, at + 1);
        }
        continue;
      }
      double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
      for (int k = 0; k < kSamples; ++k) {
        const auto px = frame.to_pixel(piece.point(k, d));
        for (int c = 0; c < 2; ++c) {
          lo[c] = std::min(lo[c], px[c]);
          hi[c] = std::max(hi[c], px[c]);
        }
      }
      const double size = std::max(hi[0] - lo[0], hi[1] - lo[1]);
      const double pad = 0.5 * size + 1.0;  // the estimate may miss the piece's rim
      if (hi[0] + pad < 0.0 || lo[0] - pad >= width || hi[1] + pad < 0.0 || lo[1] - pad >= height) continue;
      if (size < cut || piece.mass < min_mass || at + 1 == kMaxDepth || w.nodes > budget) {
        // A piece above the prefix is shared by many jobs: the one below it by 0s plots it.
        if (in_prefix && std::any_of(w.digits.begin() + at + 1, w.digits.end(), [](std::uint32_t v) { return v; }))
          return;
        leaf(piece, *w.acc);
        ++w.leaves;
        if (in_prefix) return;
        continue;
      }
      if (!piece.linear && size < kLinearBelow) linearise(piece);
      descend(w, at + 1);
    }
  }

  /// Jobs [first, last) on `threads` threads: integer sums, the same for any grouping.
  Accumulator accumulate(const RenderOptions& options, std::uint64_t first, std::uint64_t last, int threads,
                         std::uint64_t& leaves) const {
    check_memory(threads * Accumulator::bytes(frame.width(), frame.height(), true, ifs.dim() - 2),
                 "a " + std::to_string(frame.width()) + "x" + std::to_string(frame.height()) +
                     " point-recursive image on " + std::to_string(threads) + " threads");
    std::vector<Accumulator> acc;
    for (int t = 0; t < threads; ++t) acc.push_back(empty());
    std::atomic<std::uint64_t> count{0};
    parallel_jobs(
        last - first, threads,
        [&](std::size_t index, int worker) {
          Walk w;
          w.level.resize(kMaxDepth + 2);
          w.acc = &acc[worker];
          w.digits.resize(prefix);
          std::uint64_t job = first + index;
          for (int l = prefix - 1; l >= 0; --l) {
            w.digits[l] = static_cast<std::uint32_t>(job % ifs.size());
            job /= ifs.size();
          }
          Piece& root = w.level[0];
          root.q = samples[0];
          root.images = samples;
          root.linear = depth > 0;
          descend(w, 0);
          count += w.leaves;
        },
        options.progress);
    for (std::size_t t = 1; t < acc.size(); ++t) acc[0].merge(acc[t]);
    leaves = count;
    return std::move(acc[0]);
  }
};

}  // namespace

Raster point_recursive(const Ifs& ifs, const RenderOptions& options, const Renderer& renderer) {
  const Setup setup(ifs, options, renderer);
  const int threads = options.distribute ? 1 : resolve_threads(options.threads);
  Accumulator acc = setup.empty();
  std::uint64_t leaves = 0;
  if (options.distribute) {
    for (std::string_view bytes : options.distribute(0, setup.jobs, options.depth)) acc.merge_encoded(bytes);
  } else {
    acc = setup.accumulate(options, 0, setup.jobs, threads, leaves);
  }
  Raster raster;
  describe_channels(ifs, raster);
  acc.finish(raster);
  raster.pixel_size = setup.frame.pixel_size();
  raster.points = leaves;
  return raster;
}

std::string point_recursive_jobs(const Ifs& ifs, const RenderOptions& options, const Renderer& renderer,
                                 std::uint64_t first, std::uint64_t last) {
  const Setup setup(ifs, options, renderer);
  last = std::min(last, setup.jobs);
  if (first >= last) return setup.empty().encode();
  std::uint64_t leaves = 0;
  const int threads = static_cast<int>(std::min<std::uint64_t>(resolve_threads(options.threads), last - first));
  return setup.accumulate(options, first, last, threads, leaves).encode();
}

}  // namespace ifsforge::polar
