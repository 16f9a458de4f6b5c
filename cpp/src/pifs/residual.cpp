#include "ifsforge/pifs/residual.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/pifs/planes.h"
#include "ifsforge/pifs/range_coder.h"

namespace ifsforge {
namespace {

constexpr int kN = kResidualBlock, kCoefficients = kN * kN;
/// Rounding offset of the quantiser: below one half, so a coefficient just over half a step,
/// which costs bits and saves little error, becomes zero (a dead zone around 0).
constexpr double kRounding = 1.0 / 3.0;
constexpr int kBands = 10;
constexpr int kMaxMagnitude = 32767;

struct Tables {
  std::array<int, kCoefficients> zigzag{};  ///< zigzag index → row-major position
  std::array<int, kCoefficients> band{};    ///< zigzag index → context band (coarser for high frequencies)
  Tables() {
    int i = 0;
    for (int d = 0; d < 2 * kN - 1; ++d)
      for (int k = 0; k <= d; ++k) {
        const int a = d % 2 ? k : d - k, b = d - a;  // a: row, alternating direction per diagonal
        if (a < kN && b < kN) zigzag[i++] = a * kN + b;
      }
    static constexpr int edges[kBands] = {0, 1, 3, 6, 10, 15, 21, 28, 36, 49};
    for (int z = 0; z < kCoefficients; ++z) {
      int b = 0;
      while (b + 1 < kBands && z >= edges[b + 1]) ++b;
      band[z] = b;
    }
  }
};
const Tables& tables() {
  static const Tables t;
  return t;
}

/// The 8-point DCT-II basis (orthonormal): b[k·8 + j] is frequency k at pixel j.
const std::vector<double>& basis() {
  static const std::vector<double> b = [] {
    std::vector<double> v(kCoefficients);
    const double pi = 3.14159265358979323846;
    for (int k = 0; k < kN; ++k)
      for (int j = 0; j < kN; ++j)
        v[k * kN + j] = (k == 0 ? std::sqrt(1.0 / kN) : std::sqrt(2.0 / kN)) * std::cos(pi * k * (2 * j + 1) / (2.0 * kN));
    return v;
  }();
  return b;
}

int blocks_along(int size) { return (size + kN - 1) / kN; }

/// Context models shared by encoder and decoder (they visit blocks and coefficients alike).
struct ResidualModels {
  BitModel coded[3];                 ///< block has a nonzero coefficient; context: coded neighbours
  BitModel significant[kBands][3];   ///< context: band, nonzero same coefficient left and above
  BitModel last[kBands];             ///< no nonzero coefficient after this one
  BitModel above_one[kBands];
  BitModel sign;
  BitModel length[3][32];
  BitModel tail[3][25][24];
};

/// Walks the blocks in raster order with the contexts each one's coding needs. Whether a block
/// has a nonzero coefficient is remembered once it is known (all at once when encoding, block
/// by block when decoding), not scanned again for each neighbour that asks.
struct BlockWalk {
  int bx, by;
  const std::vector<std::int16_t>& c;
  std::vector<std::uint8_t> nonzero = std::vector<std::uint8_t>(std::size_t(bx) * by, 0);
  bool any(int b) const {
    for (int z = 0; z < kCoefficients; ++z)
      if (c[std::size_t(b) * kCoefficients + z]) return true;
    return false;
  }
  void remember(int b) { nonzero[std::size_t(b)] = any(b); }
  int coded_context(int x, int y) const {
    return (x > 0 && nonzero[std::size_t(y) * bx + x - 1]) + (y > 0 && nonzero[std::size_t(y - 1) * bx + x]);
  }
  int neighbour_context(int x, int y, int z) const {
    return (x > 0 && c[std::size_t(y * bx + x - 1) * kCoefficients + z] != 0) +
           (y > 0 && c[std::size_t((y - 1) * bx + x) * kCoefficients + z] != 0);
  }
};

int magnitude_group(int band) { return band < 2 ? 0 : band < 5 ? 1 : 2; }

/// The residual's entropy coder, a row of blocks at a time in raster order: each block's
/// contexts read only its left and upper neighbours, so a row can be coded as soon as it and the
/// rows above are quantised. `Sink` is RangeEncoder for the file's bytes, RangeSizer where only
/// their count is needed (the rate control).
template <class Sink>
class BlockRowCoder {
 public:
  BlockRowCoder(const std::vector<std::int16_t>& coefficients, int bx, int by)
      : walk_{bx, by, coefficients}, models_(std::make_unique<ResidualModels>()) {}
  void row(int y) {
    const Tables& t = tables();
    ResidualModels& m = *models_;
    const int bx = walk_.bx;
    for (int x = 0; x < bx; ++x) walk_.remember(y * bx + x);
    auto level = [&](int band, int v) {
      const int a = std::abs(v);
      rc_.bit(m.above_one[band], a > 1);
      if (a > 1) rc_.integer(m.length[magnitude_group(band)], m.tail[magnitude_group(band)], unsigned(a - 2));
      rc_.bit(m.sign, v < 0);
    };
    for (int x = 0; x < bx; ++x) {
      const std::int16_t* c = walk_.c.data() + (std::size_t(y) * bx + x) * kCoefficients;
      const bool coded = walk_.nonzero[std::size_t(y) * bx + x] != 0;
      rc_.bit(m.coded[walk_.coded_context(x, y)], coded);
      if (!coded) continue;
      int last = kCoefficients - 1;
      while (c[last] == 0) --last;
      int z = 0;
      for (; z < kCoefficients - 1; ++z) {
        const int band = t.band[z];
        rc_.bit(m.significant[band][walk_.neighbour_context(x, y, z)], c[z] != 0);
        if (c[z] == 0) continue;
        level(band, c[z]);
        rc_.bit(m.last[band], z == last);
        if (z == last) break;
      }
      if (z == kCoefficients - 1) level(t.band[z], c[z]);  // reached only when it is the last nonzero
    }
  }
  Sink& sink() { return rc_; }

 private:
  BlockWalk walk_;
  std::unique_ptr<ResidualModels> models_;
  Sink rc_;
};

}  // namespace

class PifsResidualRows::Coder : public BlockRowCoder<RangeSizer> {
 public:
  using BlockRowCoder<RangeSizer>::BlockRowCoder;
};

PifsResidualRows::PifsResidualRows(int width, int height, double step) : width_(width), height_(height) {
  if (!(step * kResidualStepScale <= 65535)) return;
  q_ = std::max(1, int(std::lround(step * kResidualStepScale)));
  bx_ = blocks_along(width);
  by_ = blocks_along(height);
  residual_.coefficients.assign(std::size_t(bx_) * by_ * kCoefficients, 0);
  nonzero_.assign(std::size_t(by_), 0);
  coder_ = std::make_unique<Coder>(residual_.coefficients, bx_, by_);
}

PifsResidualRows::~PifsResidualRows() = default;

void PifsResidualRows::code(int row) { coder_->row(row); }

void PifsResidualRows::quantise(int j, const PifsRaster& target, const PifsRaster& decoded) {
  const int width = width_, height = height_, bx = bx_;
  const double step = double(q_) / kResidualStepScale;
  const Tables& t = tables();
  const std::vector<double>& b = basis();
  // The basis transposed, so both passes run along contiguous rows of 8 outputs (vector lanes);
  // each output still sums its 8 products in the same order as the plain loop, so the
  // coefficients are the same to the last bit.
  double bt[kCoefficients];
  for (int k = 0; k < kN; ++k)
    for (int u = 0; u < kN; ++u) bt[u * kN + k] = b[k * kN + u];
  double x[kCoefficients], row[kCoefficients], coef[kCoefficients];
  int magnitude[kCoefficients];
  for (int i = 0; i < bx; ++i) {
    // Pixels past the plane's edge repeat its last row and column: no step for the DCT to code.
    const bool inside = (i + 1) * kN <= width && (j + 1) * kN <= height;
    for (int v = 0; v < kN; ++v) {
      const int py = std::min(j * kN + v, height - 1);
      const float* tr = target.row(py);
      const float* dr = decoded.row(py);
      if (inside) {
        for (int u = 0; u < kN; ++u) x[v * kN + u] = double(tr[i * kN + u]) - double(dr[i * kN + u]);
        continue;
      }
      for (int u = 0; u < kN; ++u) {
        const int px = std::min(i * kN + u, width - 1);
        x[v * kN + u] = double(tr[px]) - double(dr[px]);
      }
    }
    // Rows: row[v][k] = Σ_u b[k][u]·x[v][u]; then columns: coef[kv][ku] = Σ_v b[kv][v]·row[v][ku].
    for (int v = 0; v < kN; ++v) {
      double* out = row + v * kN;
      for (int k = 0; k < kN; ++k) out[k] = 0;
      for (int u = 0; u < kN; ++u) {
        const double xv = x[v * kN + u];
        for (int k = 0; k < kN; ++k) out[k] += bt[u * kN + k] * xv;
      }
    }
    for (int kv = 0; kv < kN; ++kv) {
      double* out = coef + kv * kN;
      for (int k = 0; k < kN; ++k) out[k] = 0;
      for (int v = 0; v < kN; ++v) {
        const double w = b[kv * kN + v];
        for (int k = 0; k < kN; ++k) out[k] += w * row[v * kN + k];
      }
    }
    int nonzero = 0;
    for (int c = 0; c < kCoefficients; ++c) {
      const double a = std::fabs(coef[c]) / step + kRounding;
      const int m = a < kMaxMagnitude ? int(a) : kMaxMagnitude;
      magnitude[c] = coef[c] < 0 ? -m : m;
      nonzero |= m;
    }
    std::int16_t* out = residual_.coefficients.data() + (std::size_t(j) * bx + i) * kCoefficients;
    if (nonzero == 0) continue;
    nonzero_[std::size_t(j)] = 1;
    for (int z = 0; z < kCoefficients; ++z) out[z] = std::int16_t(magnitude[t.zigzag[z]]);
  }
}

PifsResidual PifsResidualRows::finish(std::size_t* coded_size) {
  const bool any = std::find(nonzero_.begin(), nonzero_.end(), 1) != nonzero_.end();
  if (coded_size) *coded_size = any ? coder_->sink().size() : 0;
  if (!any) return PifsResidual();
  residual_.step = q_;
  return std::move(residual_);
}

PifsResidual residual_quantise(const PifsRaster& target, const PifsRaster& decoded, int width, int height,
                               double step) {
  PifsResidualRows rows(width, height, step);
  for (int j = 0; j < rows.rows(); ++j) rows.quantise(j, target, decoded);
  return rows.finish();
}

std::vector<std::uint8_t> encode_residual(const PifsResidual& residual, int width, int height) {
  if (residual.step == 0) return {};
  const int bx = blocks_along(width), by = blocks_along(height);
  if (residual.coefficients.size() != std::size_t(bx) * by * kCoefficients)
    throw InputError("PIFS residual: coefficient count does not match the plane");
  BlockRowCoder<RangeEncoder> coder(residual.coefficients, bx, by);
  for (int y = 0; y < by; ++y) coder.row(y);
  return coder.sink().finish();
}

PifsResidual decode_residual(int step, int width, int height, const std::uint8_t* data, std::size_t size,
                             const std::string& where) {
  PifsResidual r;
  if (step == 0) {
    if (size != 0) throw InputError(where + ": corrupt (residual bytes without a step)");
    return r;
  }
  r.step = step;
  const Tables& t = tables();
  const int bx = blocks_along(width), by = blocks_along(height);
  r.coefficients.assign(std::size_t(bx) * by * kCoefficients, 0);
  auto m = std::make_unique<ResidualModels>();
  RangeDecoder rc(data, size, where);
  BlockWalk walk{bx, by, r.coefficients};
  auto level = [&](int band) {
    unsigned a = 1;
    if (rc.bit(m->above_one[band])) a = 2 + rc.integer(m->length[magnitude_group(band)], m->tail[magnitude_group(band)]);
    if (a > unsigned(kMaxMagnitude)) throw InputError(where + ": corrupt (residual coefficient out of range)");
    return std::int16_t(rc.bit(m->sign) ? -int(a) : int(a));
  };
  for (int y = 0; y < by; ++y)
    for (int x = 0; x < bx; ++x) {
      std::int16_t* c = r.coefficients.data() + (std::size_t(y) * bx + x) * kCoefficients;
      if (!rc.bit(m->coded[walk.coded_context(x, y)])) continue;
      int z = 0;
      for (; z < kCoefficients - 1; ++z) {
        const int band = t.band[z];
        if (!rc.bit(m->significant[band][walk.neighbour_context(x, y, z)])) continue;
        c[z] = level(band);
        if (rc.bit(m->last[band])) break;
      }
      if (z == kCoefficients - 1) c[z] = level(t.band[z]);
      walk.remember(y * bx + x);
    }
  if (rc.consumed() != size) throw InputError(where + ": corrupt (bytes left after the residual)");
  return r;
}

namespace {

/// `native` (one value per native pixel) magnified 2^log_scale times by Catmull-Rom interpolation
/// at the finer pixel centres, added to `raster`: smooth across the 8×8 blocks' edges. Each output
/// row interpolates its four native rows along x first, so no magnified copy is held.
void add_magnified(const PifsRaster& native, int log_scale, PifsRaster& raster, int threads) {
  struct Taps {
    int index[4];
    double weight[4];
  };
  const int f = 1 << log_scale;
  auto taps = [&](int j, int size) {
    Taps t;
    const double at = (j + 0.5) / f - 0.5;
    const int i = int(std::floor(at));
    const double a = at - i;
    t.weight[0] = ((-0.5 * a + 1.0) * a - 0.5) * a;
    t.weight[1] = (1.5 * a - 2.5) * a * a + 1.0;
    t.weight[2] = ((-1.5 * a + 2.0) * a + 0.5) * a;
    t.weight[3] = (0.5 * a - 0.5) * a * a;
    for (int k = 0; k < 4; ++k) t.index[k] = std::min(std::max(i - 1 + k, 0), size - 1);
    return t;
  };
  std::vector<Taps> across(std::size_t(raster.width));
  for (int x = 0; x < raster.width; ++x) across[std::size_t(x)] = taps(x, native.width);
  threads = pass_threads(threads, double(raster.width) * raster.height);
  parallel_jobs(std::size_t(raster.height), threads, [&](std::size_t y, int) {
    const Taps down = taps(int(y), native.height);
    float* out = raster.row(int(y));
    for (int x = 0; x < raster.width; ++x) {
      const Taps& h = across[std::size_t(x)];
      double s = 0;
      for (int k = 0; k < 4; ++k) {
        const float* row = native.row(down.index[k]);
        double wide = 0;
        for (int i = 0; i < 4; ++i) wide += h.weight[i] * row[h.index[i]];
        s += down.weight[k] * wide;
      }
      out[x] += float(s);
    }
  });
}

}  // namespace

void add_residual(const PifsResidual& residual, int width, int height, int log_scale, PifsRaster& raster,
                  int threads) {
  if (residual.step == 0) return;
  if (log_scale != 0) {
    // Defined on the native grid: magnified smoothly, or averaged down as the planes are.
    PifsRaster native;
    native.width = log_scale > 0 ? raster.width >> log_scale : raster.width << -log_scale;
    native.height = log_scale > 0 ? raster.height >> log_scale : raster.height << -log_scale;
    native.values.assign(std::size_t(native.width) * native.height, 0.f);
    add_residual(residual, width, height, 0, native, threads);
    if (log_scale > 0) return add_magnified(native, log_scale, raster, threads);
    const PifsRaster small = resample_area(native, raster.width, raster.height);
    for (std::size_t i = 0; i < raster.values.size(); ++i) raster.values[i] += small.values[i];
    return;
  }
  const Tables& t = tables();
  const int bx = blocks_along(width), by = blocks_along(height);
  const std::vector<double>& b = basis();
  const double step = double(residual.step) / kResidualStepScale;
  threads = pass_threads(threads, double(raster.width) * raster.height);
  parallel_jobs(std::size_t(by), threads, [&](std::size_t j, int) {
    double coef[kCoefficients], row[kCoefficients];
    for (int i = 0; i < bx; ++i) {
      const std::int16_t* c = residual.coefficients.data() + (std::size_t(j) * bx + i) * kCoefficients;
      bool any = false;
      for (int z = 0; z < kCoefficients; ++z) {
        coef[t.zigzag[z]] = c[z] * step;
        any = any || c[z] != 0;
      }
      if (!any) continue;
      for (int kv = 0; kv < kN; ++kv)
        for (int u = 0; u < kN; ++u) {
          double s = 0;
          for (int ku = 0; ku < kN; ++ku) s += coef[kv * kN + ku] * b[ku * kN + u];
          row[kv * kN + u] = s;
        }
      const int x0 = i * kN, y0 = int(j) * kN;
      for (int v = 0; v < kN && y0 + v < raster.height; ++v) {
        float* out = raster.row(y0 + v);
        for (int u = 0; u < kN && x0 + u < raster.width; ++u) {
          double s = 0;
          for (int kv = 0; kv < kN; ++kv) s += b[kv * kN + v] * row[kv * kN + u];
          out[x0 + u] += float(s);
        }
      }
    }
  });
}

}  // namespace ifsforge
