#include "ifsforge/render/mass_transport.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {
namespace {

constexpr double kUnit = 4611686018427387904.0;  // 2^62 units: the whole mass
constexpr int kWeightShift = 24;                 // weights: mass >> 24, so weighted sums fit 64 bits
constexpr double kOffsetSteps = 65536.0;         // position within a pixel: 16 bits per axis

/// The part of the interval [centre - half, centre + half] in one cell of a row or column: the
/// cell, the fraction of the interval in it and the middle of that part within the cell.
struct Overlap {
  int cell;
  double fraction, offset;
};
constexpr int kMaxCells = 8;

int overlaps(double centre, double half, int cells, Overlap* out) {
  if (!(half > 1e-9)) {
    if (!(centre >= 0.0 && centre < cells)) return 0;
    const int cell = static_cast<int>(centre);
    out[0] = {cell, 1.0, centre - cell};
    return 1;
  }
  const double lo = centre - half, hi = centre + half;
  int count = 0;
  for (int cell = std::max(0, static_cast<int>(std::floor(lo))); cell <= std::min(cells - 1, static_cast<int>(std::floor(hi))) && count < kMaxCells; ++cell) {
    const double a = std::max(lo, double(cell)), b = std::min(hi, cell + 1.0);
    if (b > a) out[count++] = {cell, (b - a) / (2.0 * half), 0.5 * (a + b) - cell};
  }
  return count;
}

/// Per pixel: C masses, then (when needed) the weight W (mass >> 24), W x the mass centroid's
/// offset within the pixel (x, y, 16-bit; when spreading), W x each channel code.
struct Layout {
  int C, ch;
  bool position;  ///< the centroid offsets are kept (spreading)
  bool weighted() const { return position || ch > 0; }
  int values() const { return C + (weighted() ? 1 : 0) + (position ? 2 : 0) + ch; }
  int weight() const { return C; }
  int offset(int axis) const { return C + 1 + axis; }
  int channel(int c) const { return C + 1 + (position ? 2 : 0) + c; }
};

}  // namespace

RendererParameter spread_parameter() {
  return {"spread", "", "box: each pixel's mass shared among the cells its image overlaps (an accurate measure); "
                        "none: all of it to one cell (the seed's rounding, sharper coverage); default: none for "
                        "binary images, box otherwise"};
}

bool spread_mass(const std::string& value, bool binary) {
  if (value.empty()) return !binary;
  if (value == "box") return true;
  if (value == "none") return false;
  throw InputError("parameter spread='" + value + "': expected box or none");
}

TransportResult transport_mass(const Ifs& ifs, const PixelSpace& space, const TransportPlan& plan,
                               const RenderOptions& options) {
  const int C = plan.components, ch = space.channels;
  const std::size_t maps = space.maps.size(), pixels = space.pixels();
  const Layout at{C, ch, plan.spread};
  const int values = at.values();
  const int threads = resolve_threads(options.threads);
  check_memory(pixels * (2.0 * 8.0 * values + 1.0 + 4.0 * ch + 12.0) + PixelScatter::bytes(pixels, values, threads),
               "a " + std::to_string(space.width) + "x" + std::to_string(space.height) + " mass image with " +
                   std::to_string(C) + " component(s)");
  const ChannelCodec codec(space.channel_lo, space.channel_hi);
  std::vector<std::uint64_t> state(pixels * values, 0), next(pixels * values, 0);
  std::vector<float> colour(pixels * ch, 0.0f);  // decoded channel means of the current state
  std::vector<float> centroid(pixels * 2, 0.5f);  // where the mass of each pixel sits in it
  // The seed's start: the same grey value on every pixel (mass spread evenly).
  const Point start = ifs.start_point();
  {
    const auto share = static_cast<std::uint64_t>(kUnit / (static_cast<double>(pixels) * C));
    for (std::size_t p = 0; p < pixels; ++p) {
      std::uint64_t* s = &state[p * values];
      for (int k = 0; k < C; ++k) s[k] = share;
      if (!at.weighted()) continue;
      s[at.weight()] = (share * C) >> kWeightShift;
      for (int axis = 0; axis < 2 && at.position; ++axis) s[at.offset(axis)] = s[at.weight()] * static_cast<std::uint64_t>(kOffsetSteps / 2);
      for (int c = 0; c < ch; ++c) s[at.channel(c)] = s[at.weight()] * codec.encode(c, start[2 + c]);
    }
  }
  const std::vector<std::uint32_t> condensation = condensation_pixels(ifs, space.frame);
  PixelScatter scatter(pixels, values, threads);
  std::vector<std::array<double, 2>> half;  // per map: half widths of the spread box
  for (const PixelMap& m : space.maps)
    half.push_back({0.5 * std::min(std::hypot(m.a, m.b), double(kMaxCells - 2)), 0.5 * std::min(std::hypot(m.c, m.d), double(kMaxCells - 2))});
  std::vector<std::uint32_t> support(pixels);  // pixels holding mass, increasing
  for (std::size_t p = 0; p < pixels; ++p) support[p] = static_cast<std::uint32_t>(p);
  TransportResult result;
  constexpr std::size_t kChunk = 1u << 14;
  for (result.iterations = 0; result.iterations < plan.max_iterations;) {
    for (std::uint32_t p : support) {
      if (!at.weighted()) break;
      const std::uint64_t* s = &state[std::size_t(p) * values];
      const double w = static_cast<double>(s[at.weight()]);
      for (int axis = 0; axis < 2 && at.position; ++axis)
        centroid[std::size_t(p) * 2 + axis] =
            w > 0 ? static_cast<float>((static_cast<double>(s[at.offset(axis)]) / w + 0.5) / kOffsetSteps) : 0.5f;
      for (int c = 0; c < ch; ++c)
        colour[std::size_t(p) * ch + c] =
            static_cast<float>(codec.decode(c, w > 0 ? static_cast<double>(s[at.channel(c)]) / w : 0.0));
    }
    const std::size_t jobs = (support.size() + kChunk - 1) / kChunk;
    const auto width = static_cast<std::uint32_t>(space.width);
    const double wd = space.width, hd = space.height;
    parallel_jobs(jobs, threads, [&](std::size_t job, int worker) {
      PixelScatter::Writer out = scatter.writer(worker);
      std::uint64_t codes[kMaxDim * 2 + 2];
      const std::size_t begin = job * kChunk, end = std::min(support.size(), (job + 1) * kChunk);
      // Support pixels are increasing: follow the row instead of dividing.
      std::uint32_t row = support[begin] / width, row_start = row * width;
      if (C == 1 && !ch && !plan.spread && maps <= 64) {
        // The seed's CMA on a binary-or-gray image: one mass per pixel, rounded to one cell.
        // Maps and weights in locals (the scatter's byte stores would force reloads).
        double m[64][7];
        for (std::size_t j = 0; j < maps; ++j) {
          const PixelMap& pm = space.maps[j];
          const double coefficients[7] = {pm.a, pm.b, pm.c, pm.d, pm.e, pm.f, plan.weight[j]};
          std::copy(coefficients, coefficients + 7, m[j]);
        }
        const double w = wd, h = hd;
        const std::uint32_t stride = width;
        for (std::size_t k = begin; k < end; ++k) {
          const std::uint32_t p = support[k];
          while (p >= row_start + stride) {
            ++row;
            row_start += stride;
          }
          const double x = p - row_start + 0.5, y = row + 0.5, mass = static_cast<double>(state[p]);
          for (std::size_t j = 0; j < maps; ++j) {
            const double share = m[j][6] * mass;
            const double tx = m[j][0] * x + m[j][1] * y + m[j][4], ty = m[j][2] * x + m[j][3] * y + m[j][5];
            if (!(share >= 0.5) || !(tx >= 0.0 && tx < w && ty >= 0.0 && ty < h)) continue;
            const std::uint64_t v = static_cast<std::uint64_t>(share + 0.5);
            out.add(static_cast<std::uint32_t>(ty) * stride + static_cast<std::uint32_t>(tx), &v);
          }
        }
        return;
      }
      for (std::size_t k = begin; k < end; ++k) {
        const std::uint32_t p = support[k];
        while (p >= row_start + width) {
          ++row;
          row_start += width;
        }
        const std::uint64_t* s = &state[std::size_t(p) * values];
        // Spreading, the mass sits about its centroid (an affine map sends the centroid of the
        // mass to the centroid of its image); rounding, at the pixel centre, as in the seed
        // (centroids drifting across pixel edges would keep the support from settling).
        Point from{}, to;
        from[0] = p - row_start + (plan.spread ? centroid[std::size_t(p) * 2] : 0.5);
        from[1] = row + (plan.spread ? centroid[std::size_t(p) * 2 + 1] : 0.5);
        for (int c = 0; c < ch; ++c) from[2 + c] = colour[std::size_t(p) * ch + c];
        for (std::size_t j = 0; j < maps; ++j) {
          double w = 0.0;
          for (int i = 0; i < C; ++i) w += plan.weight[i * maps + j] * static_cast<double>(s[i]);
          if (!(w >= 0.5)) continue;  // less than one unit of mass
          const PixelMap& m = space.maps[j];
          if (ch) {
            m.map.apply(from.data(), to.data());
          } else {
            to[0] = m.a * from[0] + m.b * from[1] + m.e;
            to[1] = m.c * from[0] + m.d * from[1] + m.f;
          }
          // The pixel's mass, spread evenly over the pixel about its centroid, lands on a
          // parallelogram about w(centroid): spread it as a box with the same mean and the same
          // variance along x and y (widths |(a, b)| and |(c, d)| in pixels) over the cells it
          // overlaps, each share keeping the centroid of its part.
          Overlap xs[kMaxCells], ys[kMaxCells];
          const double hx = plan.spread ? half[j][0] : 0.0, hy = plan.spread ? half[j][1] : 0.0;
          const int nx = overlaps(to[0], hx, space.width, xs), ny = overlaps(to[1], hy, space.height, ys);
          for (int yi = 0; yi < ny; ++yi)
            for (int xi = 0; xi < nx; ++xi) {
              const double share = w * xs[xi].fraction * ys[yi].fraction;
              if (!(share >= 0.5)) continue;
              const std::uint32_t cell = static_cast<std::uint32_t>(ys[yi].cell) * width + static_cast<std::uint32_t>(xs[xi].cell);
              if (!at.weighted()) {  // only the mass of one component changes
                out.add_one(cell, plan.target[j], static_cast<std::uint64_t>(share + 0.5));
                continue;
              }
              std::fill(codes, codes + values, 0);
              codes[plan.target[j]] = static_cast<std::uint64_t>(share + 0.5);
              if (at.weighted()) {
                const std::uint64_t weight = codes[at.weight()] = codes[plan.target[j]] >> kWeightShift;
                if (at.position) {
                  codes[at.offset(0)] = weight * std::min<std::uint64_t>(65535, static_cast<std::uint64_t>(xs[xi].offset * kOffsetSteps));
                  codes[at.offset(1)] = weight * std::min<std::uint64_t>(65535, static_cast<std::uint64_t>(ys[yi].offset * kOffsetSteps));
                }
                for (int c = 0; c < ch; ++c) codes[at.channel(c)] = weight * codec.encode(c, to[2 + c]);
              }
              out.add(cell, codes);
            }
        }
      }
    });
    result.operations += support.size() * maps;
    if (!condensation.empty() && plan.condensation_share > 0.0) {
      std::uint64_t codes[kMaxDim * 2 + 2] = {};
      codes[0] = static_cast<std::uint64_t>(plan.condensation_share * kUnit / condensation.size());
      if (at.weighted()) {
        codes[at.weight()] = codes[0] >> kWeightShift;
        for (int axis = 0; axis < 2 && at.position; ++axis) codes[at.offset(axis)] = codes[at.weight()] * static_cast<std::uint64_t>(kOffsetSteps / 2);
        for (int c = 0; c < ch; ++c) codes[at.channel(c)] = codes[at.weight()] * codec.encode(c, ifs.condensation().channels[c]);
      }
      for (std::uint32_t p : condensation) scatter.add(0, p, codes);
    }
    std::vector<std::uint32_t> grown;
    scatter.merge(next, grown);
    // Mass that left the image is dropped: rescale the rest to the whole mass.
    // The total stays near 2^62, so integer sums cannot overflow and are exact.
    std::uint64_t total = 0, old_total = 0, old_inside = 0, change = 0;
    for (std::uint32_t p : grown)
      for (int k = 0; k < C; ++k) total += next[std::size_t(p) * values + k];
    if (total == 0)
      throw InputError("all the mass left the image: the window misses the attractor of '" + ifs.name() + "'");
    const double factor = kUnit / static_cast<double>(total);
    // L1 change: |new - old| on the new support, plus the old mass where nothing arrived.
    for (std::uint32_t p : support)
      for (int k = 0; k < C; ++k) old_total += state[std::size_t(p) * values + k];
    for (std::uint32_t p : grown)
      for (int k = 0; k < C; ++k) {
        std::uint64_t& m = next[std::size_t(p) * values + k];
        m = static_cast<std::uint64_t>(static_cast<double>(m) * factor);
        const std::uint64_t old = state[std::size_t(p) * values + k];
        change += m > old ? m - old : old - m;
        old_inside += old;
      }
    change += old_total - old_inside;
    result.change = static_cast<double>(change) / kUnit;
    const bool support_changed = grown != support;
    for (std::uint32_t p : support) std::fill_n(&state[std::size_t(p) * values], values, 0);
    state.swap(next);
    support.swap(grown);
    ++result.iterations;
    report_progress(options, std::min(1.0, std::log(std::max(result.change, 1e-300)) / std::log(plan.threshold)));
    if (result.iterations >= 2 && result.change < plan.threshold && !support_changed) break;
  }
  result.mass.assign(pixels * C, 0.0);
  result.channels.assign(pixels * ch, 0.0f);
  for (std::size_t p = 0; p < pixels; ++p) {
    const std::uint64_t* s = &state[p * values];
    for (int k = 0; k < C; ++k) result.mass[p * C + k] = static_cast<double>(s[k]) / kUnit;
    const double w = at.weighted() ? static_cast<double>(s[at.weight()]) : 0.0;
    for (int c = 0; c < ch; ++c)
      result.channels[p * ch + c] = static_cast<float>(w > 0 ? codec.decode(c, static_cast<double>(s[at.channel(c)]) / w) : start[2 + c]);
  }
  return result;
}

}  // namespace ifsforge
