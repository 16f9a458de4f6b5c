#pragma once
// Private to the mass transport (render/mass_transport.h): the cells of the mass image, the
// workers' landing areas and the three step kernels (mass_transport_steps.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

#include "ifsforge/render/mass_transport.h"

namespace ifsforge::mass_transport_detail {

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

inline Words zeroed_words(std::size_t count) {
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
  const std::vector<float>& color;
  const std::vector<std::array<double, 2>>& half;
};

/// The seed's rounding without channels (5.4, 5.12.1), see mass_transport_steps.cpp.
void transport_rounded(const Step& s, std::size_t begin, std::size_t end, Landing& landing);
/// The general step: channels carried along and, when spreading, shared among overlapped cells.
void transport_spread(const Step& s, std::size_t begin, std::size_t end, Landing& landing);
/// The general step without channels, spreading (the same result as transport_spread).
void transport_box(const Step& s, std::size_t begin, std::size_t end, Landing& landing);

}  // namespace ifsforge::mass_transport_detail
