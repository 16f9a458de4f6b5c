#include "ifsforge/pifs/encoder.h"

#include <cmath>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/pifs/code_bytes.h"
#include "ifsforge/pifs/partition.h"
#include "ifsforge/pifs/plane_coding.h"
#include "ifsforge/pifs/planes.h"

namespace ifsforge {
namespace {

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
/// buys many of them.
int automatic_min_block(const Image& image, std::size_t target, double quality) {
  const double raw = double(image.width) * image.height * image.channels;
  const bool rich = target > 0 ? double(target) * PifsEncodeOptions::kFineRatio >= raw
                               : quality <= PifsEncodeOptions::kFineQuality;
  return rich ? 2 : 4;
}

}  // namespace

PifsCode pifs_encode(const Image& image, const PifsEncodeOptions& o, const ProgressCallback& progress) {
  check(image, o);
  PifsCode code;
  code.width = image.width;
  code.height = image.height;
  code.channels = image.channels;
  code.color = o.ycbcr && image.channels >= 3 ? PifsColor::YCbCr420 : PifsColor::Direct;
  const std::size_t target = size_target(image, o);
  code.min_log = log2_exact(o.min_block > 0 ? o.min_block : automatic_min_block(image, target, o.quality), "min_block");
  code.max_log = log2_exact(o.max_block, "max_block");
  code.s_bits = o.s_bits;
  code.dc_step = o.dc_step;

  // Steps 1-4: planes, then every quadtree level's candidates. The domain pools of every
  // (plane, level) are built first, then all block rows of all of them are one job list, so every
  // thread is busy from the first range block; each candidate depends on its block alone.
  const std::vector<PifsRaster> planes = image_planes(image, code.color);
  const int levels = code.max_log - code.min_log + 1;
  std::vector<PifsRaster> padded(planes.size()), halves(planes.size());
  std::vector<PifsPlaneCandidates> cands(planes.size());
  for (std::size_t k = 0; k < planes.size(); ++k) {
    PifsPlaneCandidates& c = cands[k];
    c.width = planes[k].width;
    c.height = planes[k].height;
    c.padded_width = code.padded(c.width);
    c.padded_height = code.padded(c.height);
    padded[k] = pad_plane(planes[k], c.padded_width, c.padded_height);
    halves[k] = half_plane(padded[k]);
    for (int log = code.min_log; log <= code.max_log; ++log)
      c.levels.emplace_back(std::size_t(c.padded_width >> log) * (c.padded_height >> log));
  }
  std::vector<PifsDomains> pools(planes.size() * levels);
  parallel_jobs(
      pools.size(), o.threads,
      [&](std::size_t job, int) {
        const std::size_t k = job / levels;
        pools[job] = domain_pool(halves[k], cands[k].padded_width, cands[k].padded_height,
                                 code.min_log + int(job % levels));
      },
      progress_range(progress, 0.0, 0.1));
  struct Row {
    std::size_t pool;
    int row;
  };
  std::vector<Row> rows;
  for (std::size_t p = 0; p < pools.size(); ++p)
    for (int row = 0; row < (cands[p / levels].padded_height >> pools[p].log_size); ++row) rows.push_back({p, row});
  parallel_jobs(
      rows.size(), o.threads,
      [&](std::size_t job, int) {
        const Row& r = rows[job];
        const std::size_t k = r.pool / levels;
        const PifsDomains& pool = pools[r.pool];
        PifsPlaneCandidates& c = cands[k];
        const std::size_t bx = std::size_t(c.padded_width >> pool.log_size);
        search_row(code, padded[k], halves[k], pool, o.search, r.row,
                   c.levels[pool.log_size - code.min_log].data() + r.row * bx);
      },
      progress_range(progress, 0.1, 0.9));
  pools.clear();
  code.planes.resize(planes.size());
  for (std::size_t k = 0; k < planes.size(); ++k) {
    code.planes[k].width = planes[k].width;
    code.planes[k].height = planes[k].height;
  }

  if (target == 0) {
    for (std::size_t k = 0; k < planes.size(); ++k) code.planes[k].leaves = partition_threshold(code, cands[k], o.quality);
    return code;
  }
  // Rate control: the file size falls as λ rises; bisect log λ for the largest file ≤ target.
  // Chroma samples stand for 2×2 pixels, so their errors weigh 4×.
  // Planes are partitioned and coded independently: in parallel, their sizes summed.
  std::vector<std::size_t> stream_sizes(planes.size());
  int tries = 0;
  auto with_lambda = [&](double lambda) {
    ++tries;
    parallel_jobs(
        planes.size(), o.threads,
        [&](std::size_t k, int) {
          const bool half = code.color == PifsColor::YCbCr420 && (k == 1 || k == 2);
          code.planes[k].leaves = partition_lagrangian(code, cands[k], lambda, half ? 4.0 : 1.0);
          stream_sizes[k] = encode_plane(code, code.planes[k]).size();
        },
        progress_range(progress, std::min(0.98, 0.9 + 0.002 * tries), std::min(0.99, 0.9 + 0.002 * (tries + 1))));
    return pifs_file_size(code, stream_sizes);
  };
  double lo = std::log(1e-3), hi = std::log(1e9);
  if (with_lambda(std::exp(hi)) > target)
    throw InputError("PIFS encode: cannot reach " + std::to_string(target) + " bytes (the smallest code is " +
                     std::to_string(pifs_file_size(code, stream_sizes)) + " bytes; use a larger max_block)");
  if (with_lambda(std::exp(lo)) <= target) return code;
  // λ to within 0.1%: the file size is a step function of λ, flat at that resolution.
  while (hi - lo > 1e-3) {
    const double mid = 0.5 * (lo + hi);
    if (with_lambda(std::exp(mid)) <= target) hi = mid; else lo = mid;
  }
  with_lambda(std::exp(hi));
  return code;
}

}  // namespace ifsforge
