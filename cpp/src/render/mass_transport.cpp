#include "ifsforge/render/mass_transport.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {
namespace {

constexpr double kUnit = 4611686018427387904.0;  // 2^62 units: the whole mass
constexpr int kWeightShift = 24;                 // weights: mass >> 24, so weighted sums fit 64 bits
constexpr double kOffsetSteps = 65536.0;         // position within a pixel: 16 bits per axis
constexpr std::size_t kChunk = 1u << 14;         // cells per job (a fixed decomposition)

/// The part of the interval [centre - half, centre + half] in one cell of a row or column: the
/// cell, the fraction of the interval in it and the middle of that part within the cell.
struct Overlap {
  int cell;
  double fraction, offset;
};
constexpr int kMaxCells = 8;

inline int overlaps(double centre, double half, int cells, Overlap* out) {
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

/// How the mass image is kept: cells holding a record of `values` integers, the first
/// `masses` of them masses. Rounding without channels (`by_component`): a cell per pixel of
/// each component's image (cell = component x pixels + pixel) holding that component's mass
/// alone, so that a component's image takes room only where it holds mass (in most pixels
/// of a photo-copy only one component does). Otherwise a cell per pixel holding the C masses,
/// then the weight W (mass >> 24), W x the mass centroid's offset within the pixel (x, y,
/// 16-bit; when spreading) and W x each channel code.
struct Cells {
  int C, ch;
  bool position;      ///< the centroid offsets are kept (spreading)
  bool by_component;  ///< neither centroids nor channels: one mass per cell
  std::size_t pixels;
  std::size_t count() const { return by_component ? pixels * C : pixels; }
  int masses() const { return by_component ? 1 : C; }
  int values() const { return by_component ? 1 : C + 1 + (position ? 2 : 0) + ch; }
  int weight() const { return C; }
  int offset(int axis) const { return C + 1 + axis; }
  int channel(int c) const { return C + 1 + (position ? 2 : 0) + c; }
};

/// 64-bit words from calloc: large blocks come zeroed from the system, so the pages where no
/// mass ever lands are never touched.
struct FreeWords {
  void operator()(std::uint64_t* words) const { std::free(words); }
};
using Words = std::unique_ptr<std::uint64_t[], FreeWords>;

Words zeroed_words(std::size_t count) {
  auto* words = static_cast<std::uint64_t*>(std::calloc(std::max<std::size_t>(count, 1), sizeof(std::uint64_t)));
  if (!words) throw std::bad_alloc();
  return Words(words);
}

/// One worker's landing area for a step: the values added per cell, a bit per cell touched,
/// and the mass that landed. Integer sums: totals do not depend on which worker ran which job.
struct Landing {
  Words sums, touched;
  std::uint64_t landed = 0;
};

/// A job's hold on its worker's Landing. Make it a local of the loop that writes (the mass
/// stores could otherwise alias its members); the landed mass is written back at the end.
class Writer {
 public:
  Writer(Landing& landing, const Cells& cells)
      : sums_(landing.sums.get()), touched_(landing.touched.get()), values_(cells.values()), masses_(cells.masses()),
        landed_(0), out_(landing.landed) {}
  ~Writer() { out_ += landed_; }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;
  /// Adds mass `v` to a one-value cell.
  void add_mass(std::size_t cell, std::uint64_t v) {
    touched_[cell >> 6] |= std::uint64_t(1) << (cell & 63);
    sums_[cell] += v;
    landed_ += v;
  }
  /// Adds a whole record to `cell`.
  void add(std::size_t cell, const std::uint64_t* v) {
    touched_[cell >> 6] |= std::uint64_t(1) << (cell & 63);
    std::uint64_t* s = sums_ + cell * values_;
    for (int k = 0; k < values_; ++k) s[k] += v[k];
    for (int k = 0; k < masses_; ++k) landed_ += v[k];
  }

 private:
  std::uint64_t* sums_;
  std::uint64_t* touched_;
  int values_, masses_;
  std::uint64_t landed_;
  std::uint64_t& out_;
};

/// The mass image between steps: the cells holding mass (increasing) and their records, side
/// by side in the same order, `stride` values apart (0 for the seed's start, where one record
/// stands for every cell).
struct MassImage {
  std::vector<std::uint32_t> cells;
  std::vector<std::uint64_t> records;
  std::size_t stride = 0;
  const std::uint64_t* record(std::size_t k) const { return records.data() + k * stride; }
};

/// The mass centroid within the pixel and the channel means of each cell of `image`.
void decode_records(const Cells& at, const MassImage& image, const ChannelCodec& codec, std::vector<float>& centroid,
                    std::vector<float>& colour) {
  const std::size_t cells = image.cells.size();
  centroid.assign(at.position ? cells * 2 : 0, 0.5f);
  colour.assign(cells * at.ch, 0.0f);
  for (std::size_t k = 0; k < cells; ++k) {
    const std::uint64_t* s = image.record(k);
    const double w = static_cast<double>(s[at.weight()]);
    for (int axis = 0; axis < 2 && at.position; ++axis)
      centroid[k * 2 + axis] = w > 0 ? static_cast<float>((static_cast<double>(s[at.offset(axis)]) / w + 0.5) / kOffsetSteps) : 0.5f;
    for (int c = 0; c < at.ch; ++c)
      colour[k * at.ch + c] = static_cast<float>(codec.decode(c, w > 0 ? static_cast<double>(s[at.channel(c)]) / w : 0.0));
  }
}

/// What a step reads: the maps, the plan and its weights, and the mass image with its decoded
/// centroids and channel means (per cell; spreading / colour only).
struct Step {
  const PixelSpace& space;
  const TransportPlan& plan;
  const Cells& at;
  const std::vector<double>& weight;  ///< (C + 1) x maps: the plan's, then the start's
  const ChannelCodec& codec;
  const MassImage& image;
  const std::vector<float>& centroid;
  const std::vector<float>& colour;
  const std::vector<std::array<double, 2>>& half;
};

/// The seed's start: the same grey value on every pixel (mass spread evenly), one record for
/// all. Kept by component, it is the image of a pseudo component C whose map weights (row C
/// of `weight`, after the plan's) are the sums of the components': the step from it is that
/// of the C uniform images together.
MassImage start_image(const Cells& at, const TransportPlan& plan, std::size_t maps, const ChannelCodec& codec,
                      const Point& start, std::vector<double>& weight) {
  const int C = at.C;
  weight = plan.weight;
  weight.resize((C + 1) * maps, 0.0);
  for (int i = 0; i < C; ++i)
    for (std::size_t j = 0; j < maps; ++j) weight[C * maps + j] += plan.weight[i * maps + j];
  MassImage image;
  image.cells.resize(at.pixels);
  const std::size_t first = at.by_component ? C * at.pixels : 0;
  for (std::size_t p = 0; p < at.pixels; ++p) image.cells[p] = static_cast<std::uint32_t>(first + p);
  std::vector<std::uint64_t>& s = image.records;
  s.assign(at.values(), 0);
  const auto share = static_cast<std::uint64_t>(kUnit / (static_cast<double>(at.pixels) * C));
  for (int k = 0; k < at.masses(); ++k) s[k] = share;
  if (!at.by_component) {
    s[at.weight()] = (share * C) >> kWeightShift;
    for (int axis = 0; axis < 2 && at.position; ++axis) s[at.offset(axis)] = s[at.weight()] * static_cast<std::uint64_t>(kOffsetSteps / 2);
    for (int c = 0; c < at.ch; ++c) s[at.channel(c)] = s[at.weight()] * codec.encode(c, start[2 + c]);
  }
  return image;
}

/// Map applications of a step from `cells`: each cell by each map that carries some of its
/// component's mass.
std::uint64_t map_applications(const Cells& at, const std::vector<double>& weight, const std::vector<std::uint32_t>& cells,
                               std::size_t maps) {
  if (!at.by_component) return cells.size() * maps;
  std::uint64_t count = 0;
  for (int i = 0; i <= at.C; ++i) {
    const auto first = std::lower_bound(cells.begin(), cells.end(), static_cast<std::uint32_t>(i * at.pixels));
    const auto last = std::lower_bound(first, cells.end(), static_cast<std::uint32_t>((i + 1) * at.pixels));
    const auto row = weight.begin() + i * maps;
    count += (last - first) * std::count_if(row, row + maps, [](double w) { return w > 0.0; });
  }
  return count;
}

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
    for (int c = 0; c < ch; ++c) from[2 + c] = s.colour[k * ch + c];
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

/// What a job of the settling pass sums: the L1 change against the old image on the new
/// cells, the old mass found there, the new (rescaled) mass.
struct Settled {
  std::uint64_t change = 0, old_inside = 0, total = 0;
};

/// Settles a step, over fixed ranges of cells: gathers the workers' sums into `next` in cell
/// order (clearing the landings for the next step), rescales the masses by `factor`, and sums
/// the L1 change against `image` on the new cells.
Settled settle(std::vector<Landing>& landings, const Cells& at, const MassImage& image, double factor, int threads,
               MassImage& next) {
  constexpr std::size_t kWordsPerJob = kChunk / 64;
  const int values = at.values(), masses = at.masses();
  const std::size_t words = (at.count() + 63) / 64, jobs = (words + kWordsPerJob - 1) / kWordsPerJob;
  const std::vector<std::uint32_t>& old_cells = image.cells;
  std::vector<std::size_t> offset(jobs + 1, 0);  // where each job's cells start
  parallel_jobs(jobs, threads, [&](std::size_t job, int) {
    std::size_t count = 0;
    for (std::size_t word = job * kWordsPerJob; word < std::min(words, (job + 1) * kWordsPerJob); ++word) {
      std::uint64_t bits = 0;
      for (const Landing& l : landings) bits |= l.touched[word];
      count += __builtin_popcountll(bits);
    }
    offset[job + 1] = count;
  });
  for (std::size_t job = 0; job < jobs; ++job) offset[job + 1] += offset[job];
  next.cells.resize(offset.back());
  next.records.resize(offset.back() * values);
  next.stride = values;
  std::vector<Settled> settled(jobs);
  parallel_jobs(jobs, threads, [&](std::size_t job, int) {
    const std::size_t first_word = job * kWordsPerJob, last_word = std::min(words, (job + 1) * kWordsPerJob);
    std::size_t old = std::lower_bound(old_cells.begin(), old_cells.end(), static_cast<std::uint32_t>(first_word * 64)) - old_cells.begin();
    std::size_t k = offset[job];
    Settled sum;  // in locals: the record stores could alias it
    for (std::size_t word = first_word; word < last_word; ++word) {
      std::uint64_t bits = 0;
      for (const Landing& l : landings) bits |= l.touched[word];
      for (; bits; bits &= bits - 1, ++k) {
        const std::size_t cell = word * 64 + __builtin_ctzll(bits);
        next.cells[k] = static_cast<std::uint32_t>(cell);
        std::uint64_t* r = &next.records[k * values];
        std::fill(r, r + values, 0);
        for (const Landing& l : landings) {
          if (!(l.touched[word] >> (cell & 63) & 1)) continue;
          std::uint64_t* const from = &l.sums[cell * values];
          for (int v = 0; v < values; ++v) r[v] += from[v];
          std::fill(from, from + values, 0);
        }
        // |new - old| here; the old mass where nothing arrived is what old_inside misses.
        while (old < old_cells.size() && old_cells[old] < cell) ++old;
        const std::uint64_t* before = old < old_cells.size() && old_cells[old] == cell ? image.record(old) : nullptr;
        for (int c = 0; c < masses; ++c) {
          r[c] = static_cast<std::uint64_t>(static_cast<double>(r[c]) * factor);
          const std::uint64_t o = before ? before[c] : 0;
          sum.change += r[c] > o ? r[c] - o : o - r[c];
          sum.old_inside += o;
          sum.total += r[c];
        }
      }
      for (Landing& l : landings) l.touched[word] = 0;
    }
    settled[job] = sum;
  });
  Settled all;
  for (const Settled& s : settled) {
    all.change += s.change;
    all.old_inside += s.old_inside;
    all.total += s.total;
  }
  return all;
}

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
  const std::size_t pixels = space.pixels(), maps = space.maps.size();
  const Cells at{C, ch, plan.spread, !plan.spread && ch == 0, pixels};
  const int values = at.values(), masses = at.masses();
  const std::size_t cells = at.count(), words = (cells + 63) / 64;
  const int threads = resolve_threads(options.threads);
  const std::string what = "a " + std::to_string(space.width) + "x" + std::to_string(space.height) +
                           " mass image with " + std::to_string(C) + " component(s)";
  if (static_cast<double>(pixels) * (C + 1) >= 4294967295.0) throw InputError(what + ": too many cells");
  check_memory(cells * (8.0 * values * (threads + 2) + 8.0 + 4.0 * (2 + ch) + threads / 8.0), what);
  const ChannelCodec codec(space.channel_lo, space.channel_hi);
  const Point start = ifs.start_point();
  std::vector<double> weight;  // (C + 1) x maps: the plan's, then the start's
  MassImage image = start_image(at, plan, maps, codec, start, weight), next;
  std::uint64_t old_total = image.records[0] * C * pixels;  // the mass of `image`
  const std::vector<std::uint32_t> condensation = condensation_pixels(ifs, space.frame);
  std::vector<Landing> landings(threads);
  for (Landing& l : landings) {
    l.sums = zeroed_words(cells * values);
    l.touched = zeroed_words(words);
  }
  std::vector<std::array<double, 2>> half;  // per map: half widths of the spread box
  for (const PixelMap& m : space.maps)
    half.push_back({0.5 * std::min(std::hypot(m.a, m.b), double(kMaxCells - 2)), 0.5 * std::min(std::hypot(m.c, m.d), double(kMaxCells - 2))});
  std::vector<float> centroid, colour;  // per cell: where its mass sits in it, channel means
  TransportResult result;
  for (result.iterations = 0; result.iterations < plan.max_iterations;) {
    const std::vector<std::uint32_t>& old_cells = image.cells;
    const bool box = at.position && ch == 0;  // transport_box decodes the centroids itself
    if (!at.by_component && !box) decode_records(at, image, codec, centroid, colour);
    const Step step{space, plan, at, weight, codec, image, centroid, colour, half};
    parallel_jobs((old_cells.size() + kChunk - 1) / kChunk, threads, [&](std::size_t job, int worker) {
      const std::size_t begin = job * kChunk, end = std::min(old_cells.size(), (job + 1) * kChunk);
      if (at.by_component)
        transport_rounded(step, begin, end, landings[worker]);
      else if (box)
        transport_box(step, begin, end, landings[worker]);
      else
        transport_spread(step, begin, end, landings[worker]);
    });
    result.operations += map_applications(at, weight, old_cells, maps);
    if (!condensation.empty() && plan.condensation_share > 0.0) {
      std::uint64_t codes[kMaxDim * 2 + 2] = {};
      codes[0] = static_cast<std::uint64_t>(plan.condensation_share * kUnit / condensation.size());
      if (!at.by_component) {
        codes[at.weight()] = codes[0] >> kWeightShift;
        for (int axis = 0; axis < 2 && at.position; ++axis) codes[at.offset(axis)] = codes[at.weight()] * static_cast<std::uint64_t>(kOffsetSteps / 2);
        for (int c = 0; c < ch; ++c) codes[at.channel(c)] = codes[at.weight()] * codec.encode(c, ifs.condensation().channels[c]);
      }
      Writer out(landings[0], at);
      for (std::uint32_t p : condensation) out.add(p, codes);  // component 0's image: cell = pixel
    }
    // Mass that left the image is dropped: rescale the rest to the whole mass. The total
    // stays near 2^62, so integer sums cannot overflow and are exact.
    std::uint64_t total = 0;
    for (Landing& l : landings) {
      total += l.landed;
      l.landed = 0;
    }
    if (total == 0)
      throw InputError("all the mass left the image: the window misses the attractor of '" + ifs.name() + "'");
    const double factor = kUnit / static_cast<double>(total);
    const Settled settled = settle(landings, at, image, factor, threads, next);
    // (From the start, a pseudo component, everything changes; it takes two steps to stop.)
    result.change = static_cast<double>(settled.change + (old_total - settled.old_inside)) / kUnit;
    old_total = settled.total;
    const bool support_changed = next.cells != image.cells;
    std::swap(image, next);
    ++result.iterations;
    report_progress(options, std::min(1.0, std::log(std::max(result.change, 1e-300)) / std::log(plan.threshold)));
    if (result.iterations >= 2 && result.change < plan.threshold && !support_changed) break;
  }
  result.pixel.reserve(image.cells.size());
  result.component.reserve(image.cells.size());
  result.mass.reserve(image.cells.size());
  result.channels.assign(pixels * ch, 0.0f);
  for (std::size_t p = 0; p < pixels && ch; ++p)
    for (int c = 0; c < ch; ++c) result.channels[p * ch + c] = static_cast<float>(start[2 + c]);
  for (std::size_t k = 0; k < image.cells.size(); ++k) {
    const std::uint64_t* s = image.record(k);
    const std::uint32_t cell = image.cells[k];
    const std::uint32_t pixel = static_cast<std::uint32_t>(cell % pixels);
    for (int c = 0; c < masses; ++c) {
      if (!s[c]) continue;
      result.pixel.push_back(pixel);
      result.component.push_back(at.by_component ? static_cast<int>(cell / pixels) : c);
      result.mass.push_back(static_cast<double>(s[c]) / kUnit);
    }
    const double w = at.by_component ? 0.0 : static_cast<double>(s[at.weight()]);
    for (int c = 0; c < ch; ++c)
      if (w > 0) result.channels[std::size_t(pixel) * ch + c] = static_cast<float>(codec.decode(c, static_cast<double>(s[at.channel(c)]) / w));
  }
  return result;
}

}  // namespace ifsforge
