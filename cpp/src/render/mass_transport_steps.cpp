// The step kernels of the mass transport (render/mass_transport.h): one map application of
// the Markov operator (Eq. 50, 71-72) over a range of the mass image's cells.
#include <algorithm>
#include <cmath>

#include "mass_transport_cells.h"

namespace ifsforge::mass_transport_detail {

/// The seed's rounding without channels (5.4, 5.12.1): map j sends the share weight(i, j) of
/// the mass of component i at a pixel to the pixel holding w_j(pixel centre), component
/// target[j] (Eq. 50, 72). Batch by batch (one component each) and map by map: the arithmetic
/// in plain loops over arrays (vectorised), then the neighbours landing on the same pixel
/// (about 1/|a| of them along a row for a contraction) summed and added to the image once.
void transport_rounded(const Step& s, std::size_t begin, std::size_t end, Landing& landing) {
  constexpr std::size_t kBatch = 1024;
  constexpr std::uint32_t kNowhere = 0xFFFFFFFFu;
  Writer out(landing, s.at);
  const std::size_t maps = s.space.maps.size(), pixels = s.at.pixels;
  const auto width = static_cast<std::uint32_t>(s.space.width);
  const double w = s.space.width, h = s.space.height, per_row = 1.0 / w;
  const std::uint32_t* cells = s.image.cells.data();
  const std::uint64_t* records = s.image.records.data();
  const std::size_t stride = s.image.stride;
  double x[kBatch], y[kBatch], mass[kBatch];
  std::uint32_t q[kBatch];
  std::uint64_t v[kBatch];
  for (std::size_t base = begin, n; base < end; base += n) {
    // A batch of one component's cells.
    const std::size_t i = cells[base] / pixels, first = i * pixels;
    n = std::min(kBatch, end - base);
    n = std::lower_bound(cells + base, cells + base + n, static_cast<std::uint32_t>(first + pixels)) - (cells + base);
    // Pixel centres. The row is the floor of (p + 1/2) x (1 / width), which is within
    // height x 2^-52 of (p + 1/2) / width, itself at least 1 / (2 width) from an integer.
    for (std::size_t k = 0; k < n; ++k) {
      const double p = static_cast<double>(cells[base + k] - first), row = std::floor((p + 0.5) * per_row);
      x[k] = p - row * w + 0.5;
      y[k] = row + 0.5;
      mass[k] = static_cast<double>(records[(base + k) * stride]);
    }
    for (std::size_t j = 0; j < maps; ++j) {
      const double weight = s.weight[i * maps + j];
      if (!(weight > 0.0)) continue;
      const PixelMap& m = s.space.maps[j];
      const double a = m.a, b = m.b, c = m.c, d = m.d, e = m.e, f = m.f;
      for (std::size_t k = 0; k < n; ++k) {
        const double share = weight * mass[k];
        const double tx = a * x[k] + b * y[k] + e, ty = c * x[k] + d * y[k] + f;
        // Less than one unit of mass, or off the image: nothing lands.
        const bool lands = (share >= 0.5) & (tx >= 0.0) & (tx < w) & (ty >= 0.0) & (ty < h);
        const std::uint32_t pixel = static_cast<std::uint32_t>(lands ? ty : 0.0) * width + static_cast<std::uint32_t>(lands ? tx : 0.0);
        q[k] = lands ? pixel : kNowhere;
        v[k] = lands ? static_cast<std::uint64_t>(share + 0.5) : 0;
      }
      const std::size_t image = static_cast<std::size_t>(s.plan.target[j]) * pixels;
      std::uint32_t run = kNowhere;  // the pixel being summed into, and its sum so far
      std::uint64_t run_mass = 0;
      for (std::size_t k = 0; k < n; ++k) {
        if (q[k] != run) {
          if (run_mass) out.add_mass(image + run, run_mass);
          run = q[k];
          run_mass = 0;
        }
        run_mass += v[k];
      }
      if (run_mass) out.add_mass(image + run, run_mass);
    }
  }
}

/// The general step: channels carried along and, when spreading, a pixel's mass (spread
/// evenly over the pixel about its centroid) shared among the cells its image overlaps.
void transport_spread(const Step& s, std::size_t begin, std::size_t end, Landing& landing) {
  Writer out(landing, s.at);
  const TransportPlan& plan = s.plan;
  const Cells& at = s.at;
  const std::size_t maps = s.space.maps.size();
  const int C = at.C, ch = at.ch, values = at.values();
  const auto width = static_cast<std::uint32_t>(s.space.width);
  std::uint64_t codes[kMaxDim * 2 + 2];
  // Cells are increasing: follow the row instead of dividing.
  std::uint32_t row = s.image.cells[begin] / width, row_start = row * width;
  for (std::size_t k = begin; k < end; ++k) {
    const std::uint32_t p = s.image.cells[k];
    while (p >= row_start + width) {
      ++row;
      row_start += width;
    }
    const std::uint64_t* r = s.image.record(k);
    // Spreading, the mass sits about its centroid (an affine map sends the centroid of the
    // mass to the centroid of its image); rounding, at the pixel centre, as in the seed
    // (centroids drifting across pixel edges would keep the support from settling).
    Point from{}, to;
    from[0] = p - row_start + (plan.spread ? s.centroid[k * 2] : 0.5);
    from[1] = row + (plan.spread ? s.centroid[k * 2 + 1] : 0.5);
    for (int c = 0; c < ch; ++c) from[2 + c] = s.color[k * ch + c];
    for (std::size_t j = 0; j < maps; ++j) {
      double w = 0.0;
      for (int i = 0; i < C; ++i) w += plan.weight[i * maps + j] * static_cast<double>(r[i]);
      if (!(w >= 0.5)) continue;  // less than one unit of mass
      const PixelMap& m = s.space.maps[j];
      if (ch) {
        m.map.apply(from.data(), to.data());
      } else {
        to[0] = m.a * from[0] + m.b * from[1] + m.e;
        to[1] = m.c * from[0] + m.d * from[1] + m.f;
      }
      // The pixel's mass lands on a parallelogram about w(centroid): spread it as a box with
      // the same mean and the same variance along x and y (widths |(a, b)| and |(c, d)| in
      // pixels) over the cells it overlaps, each share keeping the centroid of its part.
      Overlap xs[kMaxCells], ys[kMaxCells];
      const double hx = plan.spread ? s.half[j][0] : 0.0, hy = plan.spread ? s.half[j][1] : 0.0;
      const int nx = overlaps(to[0], hx, s.space.width, xs), ny = overlaps(to[1], hy, s.space.height, ys);
      for (int yi = 0; yi < ny; ++yi)
        for (int xi = 0; xi < nx; ++xi) {
          const double share = w * xs[xi].fraction * ys[yi].fraction;
          if (!(share >= 0.5)) continue;
          const std::uint32_t cell = static_cast<std::uint32_t>(ys[yi].cell) * width + static_cast<std::uint32_t>(xs[xi].cell);
          std::fill(codes, codes + values, 0);
          codes[plan.target[j]] = static_cast<std::uint64_t>(share + 0.5);
          const std::uint64_t weight = codes[at.weight()] = codes[plan.target[j]] >> kWeightShift;
          if (at.position) {
            codes[at.offset(0)] = weight * std::min<std::uint64_t>(65535, static_cast<std::uint64_t>(xs[xi].offset * kOffsetSteps));
            codes[at.offset(1)] = weight * std::min<std::uint64_t>(65535, static_cast<std::uint64_t>(ys[yi].offset * kOffsetSteps));
          }
          for (int c = 0; c < ch; ++c) codes[at.channel(c)] = weight * s.codec.encode(c, to[2 + c]);
          out.add(cell, codes);
        }
    }
  }
}

/// The general step without channels, spreading: as transport_spread (the same arithmetic, so
/// the same result), with each share added straight into its cell's record (mass, weight,
/// centroid offsets), the centroids decoded on the way and the overlaps along x kept as codes.
void transport_box(const Step& s, std::size_t begin, std::size_t end, Landing& landing) {
  const TransportPlan& plan = s.plan;
  const Cells& at = s.at;
  const std::size_t maps = s.space.maps.size();
  const int C = at.C, values = at.values();
  const auto width = static_cast<std::uint32_t>(s.space.width);
  const int cols = s.space.width, rows = s.space.height;
  std::uint64_t* const sums = landing.sums.get();
  std::uint64_t* const touched = landing.touched.get();
  std::uint64_t landed = 0;
  const std::uint32_t* const cells = s.image.cells.data();
  std::uint32_t row = cells[begin] / width, row_start = row * width;
  for (std::size_t k = begin; k < end; ++k) {
    const std::uint32_t p = cells[k];
    while (p >= row_start + width) {
      ++row;
      row_start += width;
    }
    const std::uint64_t* r = s.image.record(k);
    // The centroid as decode_records gives it, decoded here (in parallel, no pass of its own).
    const double mean = static_cast<double>(r[at.weight()]);
    float centroid[2] = {0.5f, 0.5f};
    for (int axis = 0; axis < 2; ++axis)
      if (mean > 0) centroid[axis] = static_cast<float>((static_cast<double>(r[at.offset(axis)]) / mean + 0.5) / kOffsetSteps);
    Point from{};
    from[0] = p - row_start + static_cast<double>(centroid[0]);
    from[1] = row + static_cast<double>(centroid[1]);
    for (std::size_t j = 0; j < maps; ++j) {
      double w = 0.0;
      for (int i = 0; i < C; ++i) w += plan.weight[i * maps + j] * static_cast<double>(r[i]);
      if (!(w >= 0.5)) continue;  // less than one unit of mass
      const PixelMap& m = s.space.maps[j];
      const double tx = m.a * from[0] + m.b * from[1] + m.e;
      const double ty = m.c * from[0] + m.d * from[1] + m.f;
      Overlap xs[kMaxCells], ys[kMaxCells];
      const int nx = overlaps(tx, s.half[j][0], cols, xs), ny = overlaps(ty, s.half[j][1], rows, ys);
      if (!nx || !ny) continue;
      std::uint64_t xcode[kMaxCells];
      for (int xi = 0; xi < nx; ++xi) xcode[xi] = std::min<std::uint64_t>(65535, static_cast<std::uint64_t>(xs[xi].offset * kOffsetSteps));
      const int target = plan.target[j];
      for (int yi = 0; yi < ny; ++yi) {
        const std::uint64_t ycode = std::min<std::uint64_t>(65535, static_cast<std::uint64_t>(ys[yi].offset * kOffsetSteps));
        const std::size_t line = static_cast<std::size_t>(ys[yi].cell) * width;
        for (int xi = 0; xi < nx; ++xi) {
          const double share = w * xs[xi].fraction * ys[yi].fraction;
          if (!(share >= 0.5)) continue;
          const std::size_t cell = line + static_cast<std::uint32_t>(xs[xi].cell);
          const auto mass = static_cast<std::uint64_t>(share + 0.5);
          const std::uint64_t weight = mass >> kWeightShift;
          touched[cell >> 6] |= std::uint64_t(1) << (cell & 63);
          std::uint64_t* const out = sums + cell * values;
          out[target] += mass;
          out[C] += weight;
          out[C + 1] += weight * xcode[xi];
          out[C + 2] += weight * ycode;
          landed += mass;
        }
      }
    }
  }
  landing.landed += landed;
}

}  // namespace ifsforge::mass_transport_detail
