#include "ifsforge/pifs/encoder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/pifs/code_bytes.h"
#include "ifsforge/pifs/decoder.h"
#include "ifsforge/pifs/partition.h"
#include "ifsforge/pifs/plane_coding.h"
#include "ifsforge/pifs/planes.h"
#include "ifsforge/pifs/residual.h"
#include "decode_steps.h"
#include "rate_search.h"
#include "staged_rounds.h"

namespace ifsforge {
namespace {

/// λ per squared residual step (see the rate control): a high-rate uniform quantiser trades
/// about 0.12·step² of squared error per bit; a larger value, measured on the tuning photographs
/// (camera, coffee, astronaut at 5:1 to 50:1), gives the residual layer a finer step.
constexpr double kResidualLambda = 0.3;

int log2_exact(int v, const char* what) {
  int l = 0;
  while ((1 << l) < v) ++l;
  if ((1 << l) != v) throw InputError(std::string("PIFS encode: ") + what + " must be a power of two");
  return l;
}

void check(const Image& image, const PifsEncodeOptions& o) {
  if (image.width < 1 || image.height < 1) throw InputError("PIFS encode: the image is empty");
  if (image.channels < 1 || image.channels > 4) throw InputError("PIFS encode: images have 1 to 4 channels");
  if (image.width > 32768 || image.height > 32768) throw InputError("PIFS encode: image larger than 32768 pixels");
  if ((o.min_block != 0 && o.min_block < 2) || o.max_block > 256 || o.min_block > o.max_block)
    throw InputError("PIFS encode: block sizes must satisfy 2 <= min_block <= max_block <= 256 (min_block 0: automatic)");
  if (o.s_bits < 2 || o.s_bits > 8) throw InputError("PIFS encode: s_bits must be in 2..8");
  if (o.dc_step < 1 || o.dc_step > 64) throw InputError("PIFS encode: dc_step must be in 1..64");
  if (o.ratio < 0 || !std::isfinite(o.ratio)) throw InputError("PIFS encode: ratio must be positive");
  if (!(o.quality >= 0) || !std::isfinite(o.quality)) throw InputError("PIFS encode: quality must be >= 0");
}

/// The file size asked for (bytes), 0 for a quality request.
std::size_t size_target(const Image& image, const PifsEncodeOptions& o) {
  if (o.bytes > 0 || o.ratio <= 0) return o.bytes;
  // A ratio is honoured or refused: one that asks for less than a byte is not a quality request.
  const double raw = double(image.width) * image.height * image.channels;
  if (raw / o.ratio < 1.0)
    throw InputError("PIFS encode: ratio " + std::to_string(o.ratio) + " asks for under one byte of a " +
                     std::to_string(std::size_t(raw)) + "-byte image");
  return std::size_t(raw / o.ratio);
}

/// The automatic smallest range cell: 2×2 cells pay for their search only where the budget
/// buys many of them. With the residual layer, cells below its 8×8 blocks cost more than the
/// DCT's refinement of a larger cell does.
int automatic_min_block(const Image& image, std::size_t target, double quality, bool residual, int max_block) {
  if (residual && target > 0) return std::min(kResidualBlock, max_block);
  const double raw = double(image.width) * image.height * image.channels;
  const bool rich = target > 0 ? double(target) * PifsEncodeOptions::kFineRatio >= raw
                               : quality <= PifsEncodeOptions::kFineQuality;
  return rich ? 2 : 4;
}

/// The code of `image` with its colour coded as `color`, under `target` bytes (0: o.quality);
/// `lambda`, when given, receives the rate control's λ (0 without a size target).
PifsCode encode_as(const Image& image, const PifsEncodeOptions& o, PifsColor color, std::size_t target,
                   const ProgressCallback& progress, double* lambda = nullptr) {
  PifsCode code;
  code.width = image.width;
  code.height = image.height;
  code.channels = image.channels;
  code.color = color;
  code.min_log = log2_exact(o.min_block > 0 ? o.min_block : automatic_min_block(image, target, o.quality, o.residual, o.max_block), "min_block");
  code.max_log = log2_exact(o.max_block, "max_block");
  code.s_bits = o.s_bits;
  code.dc_step = o.dc_step;

  // Steps 1-4: planes, then every quadtree level's candidates. The planes are converted,
  // padded and halved in the first round of the job lists below (staged_rounds.h), a stage each
  // in parts of rows, on the threads that then search and run the rate control, so no step of
  // the encode is left to one thread and none waits for threads to wake between steps. The
  // domain pools of every (plane, level) are built first, then all block rows of all of them
  // are searched in one job list, so every thread is busy from the first range block; each
  // candidate depends on its block alone.
  const std::vector<std::array<int, 2>> plane_size = plane_sizes(image, code.color);
  const std::size_t plane_count = plane_size.size();
  const int levels = code.max_log - code.min_log + 1;
  std::vector<PifsRaster> padded(plane_count), halves(plane_count);
  std::vector<PifsPlaneCandidates> cands(plane_count);
  for (std::size_t k = 0; k < plane_count; ++k) {
    PifsPlaneCandidates& c = cands[k];
    c.width = plane_size[k][0];
    c.height = plane_size[k][1];
    c.padded_width = code.padded(c.width);
    c.padded_height = code.padded(c.height);
    for (int log = code.min_log; log <= code.max_log; ++log)
      c.levels.emplace_back(std::size_t(c.padded_width >> log) * (c.padded_height >> log));
  }
  // The set-up round's stages: the rasters (a part each), then the conversion, the padding and
  // the halving, each in parts of about 2^16 samples of rows.
  const std::size_t setup_parts =
      std::clamp<std::size_t>(std::size_t(image.width) * image.height * image.channels >> 16, 1, 64);
  const auto setup_step = [&](std::size_t stage, std::size_t part) {
    const auto rows = [&](int count, auto&& run) {
      run(int(std::size_t(count) * part / setup_parts), int(std::size_t(count) * (part + 1) / setup_parts));
    };
    if (stage == 0) {
      const std::size_t k = part % plane_count;
      if (part < plane_count) padded[k] = plane_raster(cands[k].padded_width, cands[k].padded_height);
      else halves[k] = plane_raster(cands[k].padded_width / 2, cands[k].padded_height / 2);
    } else if (stage == 1) {
      rows(conversion_rows(image, code.color), [&](int a, int b) { convert_rows(image, code.color, padded, a, b); });
    } else {
      for (std::size_t k = 0; k < plane_count; ++k) {
        const PifsPlaneCandidates& c = cands[k];
        if (stage == 2)
          rows(c.padded_height, [&](int a, int b) { pad_rows(padded[k], c.width, c.height, a, b); });
        else
          rows(c.padded_height / 2, [&](int a, int b) { half_rows(padded[k], halves[k], a, b); });
      }
    }
  };
  // The search is the first round of the job lists below (staged_rounds.h, on the same threads as
  // the rate control's rounds): a unit is one domain pool, largest first; its first step builds
  // the pool, its middle steps search its block rows. A thread that finds the largest pool's
  // tree still being built works on the other pools' rows meanwhile.
  std::vector<PifsDomains> pools(plane_count * levels);
  std::vector<std::size_t> pool_order(pools.size());
  for (std::size_t p = 0; p < pools.size(); ++p) pool_order[p] = p;
  const auto pool_area = [&](std::size_t p) {
    const PifsPlaneCandidates& c = cands[p / levels];
    return double(c.padded_width) * c.padded_height / double(1 << 2 * (p % levels));
  };
  std::stable_sort(pool_order.begin(), pool_order.end(),
                   [&](std::size_t a, std::size_t b) { return pool_area(a) > pool_area(b); });
  std::vector<std::size_t> pool_rows(pools.size());
  for (std::size_t u = 0; u < pools.size(); ++u)
    pool_rows[u] = std::size_t(cands[pool_order[u] / levels].padded_height >> (code.min_log + int(pool_order[u] % levels)));
  code.planes.resize(plane_count);
  for (std::size_t k = 0; k < plane_count; ++k) {
    code.planes[k].width = cands[k].width;
    code.planes[k].height = cands[k].height;
  }

  // Rate control: the file size falls as λ rises; search log λ for the largest file ≤ target.
  // Chroma samples stand for 2×2 pixels, so their errors weigh 4× (and their residual step
  // halves). The residual layer's step follows λ (step² = λ / kResidualLambda), so the quadtree
  // and the residual trade error for bits at the same price. Each round tries two values of
  // λ at once; the values tried never depend on the thread count.
  struct Probe {
    double log_lambda = 0;
    std::vector<PifsPlane> planes;
    std::size_t size = 0;
  };
  // The search (rate_search.h): a bracket of log λ narrowed by interpolation, two values a
  // round, starting near the λ the target's bits per sample suggest.
  LambdaBracket bracket(target, lambda_guess(image, target));
  std::vector<Probe> probes(2);
  Probe best;  // done() holds only once a value has fitted
  // A unit is one plane of one probe, the largest planes and lowest λ (the costliest) first.
  // Its first step cuts the quadtree and decodes the coarsest level; its stages' parts, shared
  // by every free thread (the costliest unit's decode is on the round's longest path), make
  // what the decoder shows at 1× (each doubling, then the deblocking, as pifs_decode does);
  // its middle steps quantise the residual a block row each, then code the transforms (only
  // their size is needed, so off the path to the residual); the entropy coder, sequential,
  // follows the rows one by one. All rounds are job lists on the same threads, so both
  // threads stay busy however the units' costs differ.
  const std::size_t count = probes.size(), units = count * plane_count;
  std::vector<PifsStreamSizes> sizes(units);
  std::vector<std::unique_ptr<PlaneDecodeSteps>> decoded(units);
  std::vector<std::unique_ptr<PifsResidualRows>> residuals(units);
  std::vector<std::size_t> block_rows(units, 0);
  if (o.residual)
    for (std::size_t u = 0; u < units; ++u)
      block_rows[u] = std::size_t(cands[u / count].height + kResidualBlock - 1) / kResidualBlock;
  int rounds = 0;  // started: the set-up, the search, then the rate control's
  enum class Phase { SetUp, Search, Rate } phase = Phase::SetUp;
  // Between rounds, on one thread: first the set-up, then the search; then the sizes of the
  // round that ended narrow the bracket, which gives the next two values of λ.
  const auto next_round = [&](std::vector<std::size_t>& middles) {
    if (++rounds <= 2) {
      phase = rounds == 1 ? Phase::SetUp : Phase::Search;
      middles = rounds == 1 ? std::vector<std::size_t>{0} : pool_rows;
      return true;
    }
    phase = Phase::Rate;
    if (target == 0) return false;
    if (rounds > 3) {
      for (std::size_t p = 0; p < count; ++p) {
        std::vector<PifsStreamSizes> stream_sizes(plane_count);
        for (std::size_t k = 0; k < plane_count; ++k) stream_sizes[k] = sizes[k * count + p];
        probes[p].size = pifs_file_size(code, stream_sizes);
      }
      for (const Probe& p : probes)
        if (p.log_lambda >= LambdaBracket::kHighest && p.size > target)
          throw InputError("PIFS encode: cannot reach " + std::to_string(target) + " bytes (the smallest code is " +
                           std::to_string(p.size) + " bytes; use a larger max_block)");
      const int fit = bracket.update({{{probes[0].log_lambda, probes[0].size}, {probes[1].log_lambda, probes[1].size}}});
      if (fit >= 0) std::swap(best, probes[std::size_t(fit)]);  // the old best's planes are freed below
    }
    if (bracket.done()) return false;
    const std::array<double, 2> next = bracket.next();
    probes[0].log_lambda = next[0];
    probes[1].log_lambda = next[1];
    // The planes of the probes no longer needed are freed by the first steps (on every thread).
    for (Probe& p : probes) p.planes.resize(plane_count);
    sizes.assign(units, {});
    middles = block_rows;
    for (std::size_t& m : middles) ++m;  // the transforms' code
    return true;
  };
  // The search's share of the progress (the set-up's is nil), then the rate control's rounds.
  ProgressCallback rounds_progress;
  if (progress)
    rounds_progress = [&](double rounds) {
      const double r = std::max(0.0, rounds - 1);
      return progress(r <= 1 ? 0.9 * r : std::min(0.99, 0.9 + 0.008 * (r - 1)));
    };
  staged_rounds(
      next_round, o.threads,
      [&](std::size_t u) -> std::vector<std::size_t> {
        if (phase == Phase::SetUp) return {2 * plane_count, setup_parts, setup_parts, setup_parts};
        if (phase == Phase::Search) {
          const std::size_t p = pool_order[u], k = p / levels;
          pools[p] = domain_pool(halves[k], cands[k].padded_width, cands[k].padded_height,
                                 code.min_log + int(p % levels), o.search.mode == PifsDomainSearch::Tree);
          return {};
        }
        const std::size_t k = u / count, p = u % count;
        const bool half = code.halved(k);
        PifsPlane& plane = probes[p].planes[k];
        plane = PifsPlane();
        plane.width = cands[k].width;
        plane.height = cands[k].height;
        const double lambda = std::exp(probes[p].log_lambda);
        plane.leaves = partition_lagrangian(code, cands[k], lambda, half ? 4.0 : 1.0);
        if (!o.residual) return {};
        const double step = std::sqrt(lambda / kResidualLambda) * (half ? 0.5 : 1.0);
        residuals[u] = std::make_unique<PifsResidualRows>(plane.width, plane.height, step);
        decoded[u] = std::make_unique<PlaneDecodeSteps>(code, plane);
        return decoded[u]->stages();
      },
      [&](std::size_t u, std::size_t stage, std::size_t part) {
        if (phase == Phase::SetUp) setup_step(stage, part);
        else decoded[u]->run(stage, part);
      },
      [&](std::size_t u, std::size_t row) {
        if (phase == Phase::Search) {
          const std::size_t k = pool_order[u] / levels;
          const PifsDomains& pool = pools[pool_order[u]];
          PifsPlaneCandidates& c = cands[k];
          const std::size_t bx = std::size_t(c.padded_width >> pool.log_size);
          search_row(code, padded[k], halves[k], pool, o.search, int(row),
                     c.levels[pool.log_size - code.min_log].data() + row * bx);
          return;
        }
        if (row == block_rows[u]) {
          sizes[u].transforms = encode_plane(code, probes[u % count].planes[u / count]).size();
          return;
        }
        // A step too coarse for any coefficient has no rows.
        if (int(row) < residuals[u]->rows()) residuals[u]->quantise(int(row), padded[u / count], decoded[u]->raster());
      },
      [&](std::size_t u, std::size_t row) {
        if (phase == Phase::Search) {
          if (row + 1 == pool_rows[u]) pools[pool_order[u]] = PifsDomains();  // its rows are searched
          return;
        }
        if (row == block_rows[u]) return;
        if (int(row) < residuals[u]->rows()) residuals[u]->code(int(row));
        if (row + 1 < block_rows[u]) return;
        PifsPlane& plane = probes[u % count].planes[u / count];
        plane.residual = residuals[u]->finish(&sizes[u].residual);
        sizes[u].residual_step = plane.residual.step;
        residuals[u].reset();
        decoded[u].reset();
      },
      rounds_progress);
  if (target == 0) {
    for (std::size_t k = 0; k < plane_count; ++k) code.planes[k].leaves = partition_threshold(code, cands[k], o.quality);
    return code;
  }
  code.planes = std::move(best.planes);
  if (lambda) *lambda = std::exp(best.log_lambda);
  return code;
}

}  // namespace

PifsCode pifs_encode(const Image& image, const PifsEncodeOptions& o, const ProgressCallback& progress) {
  check(image, o);
  const std::size_t target = size_target(image, o);
  if (!o.ycbcr || image.channels < 3) return encode_as(image, o, PifsColor::Direct, target, progress);
  if (o.chroma != PifsChroma::Auto || target == 0)
    return encode_as(image, o, o.chroma == PifsChroma::Full ? PifsColor::YCbCr444 : PifsColor::YCbCr420, target,
                     progress);
  // Automatic chroma: half-size chroma (Step 2) wins wherever the budget is tight, but caps the
  // quality of a rich one at what averaging the chroma 2×2 loses. So where that loss is a
  // large share of the 4:2:0 code's own error, full-size chroma is coded too and the code
  // whose decode is nearer the image (RGB squared error) is kept.
  const double halving = chroma_halving_error(image, o.threads, progress_range(progress, 0.0, 0.0));
  const bool may_try = halving > PifsEncodeOptions::kChromaErrorFloor;
  double lambda = 0;
  PifsCode half =
      encode_as(image, o, PifsColor::YCbCr420, target, progress_range(progress, 0.0, may_try ? 0.5 : 1.0), &lambda);
  if (!may_try) return half;
  PifsDecodeOptions decode;
  decode.threads = o.threads;
  // The 4:2:0 code's RGB error, foreseen from its residual step without decoding (a decode of
  // a small image is one thread's work): a uniform quantiser of step q leaves q²/12 per sample,
  // the chroma's step is half the luma's, and R, G, B take Y's error once each and the chroma's
  // through the inverse matrix (Cb: 0.344² + 1.772², Cr: 1.402² + 0.714²).
  // Without the residual layer there is no step: the 4:2:0 code is decoded, once.
  const auto error_of = [&](const PifsCode& code) { return squared_error(image, pifs_decode(code, decode), o.threads); };
  const double half_error = o.residual ? -1.0 : error_of(half);
  const double foreseen = o.residual ? (3.0 + (3.258 + 2.476) / 4) * (lambda / kResidualLambda) / 12 / 3 : half_error;
  if (halving < PifsEncodeOptions::kFullChromaShare * foreseen) return half;
  PifsCode full = encode_as(image, o, PifsColor::YCbCr444, target, progress_range(progress, 0.5, 1.0));
  return error_of(full) < (half_error >= 0 ? half_error : error_of(half)) ? full : half;
}

}  // namespace ifsforge
