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
#include "mass_transport_cells.h"

namespace ifsforge {
namespace mass_transport_detail {
namespace {

/// The mass centroid within the pixel and the channel means of each cell of `image`.
void decode_records(const Cells& at, const MassImage& image, const ChannelCodec& codec, std::vector<float>& centroid,
                    std::vector<float>& color) {
  const std::size_t cells = image.cells.size();
  centroid.assign(at.position ? cells * 2 : 0, 0.5f);
  color.assign(cells * at.ch, 0.0f);
  for (std::size_t k = 0; k < cells; ++k) {
    const std::uint64_t* s = image.record(k);
    const double w = static_cast<double>(s[at.weight()]);
    for (int axis = 0; axis < 2 && at.position; ++axis)
      centroid[k * 2 + axis] = w > 0 ? static_cast<float>((static_cast<double>(s[at.offset(axis)]) / w + 0.5) / kOffsetSteps) : 0.5f;
    for (int c = 0; c < at.ch; ++c)
      color[k * at.ch + c] = static_cast<float>(codec.decode(c, w > 0 ? static_cast<double>(s[at.channel(c)]) / w : 0.0));
  }
}

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

/// What a job of the settling pass sums: the L1 change against the old image on the new
/// cells, the old mass found there, the new (rescaled) mass.
struct Settled {
  std::uint64_t change = 0, old_inside = 0, total = 0;
};

/// Settles a step, over fixed ranges of cells: gathers the workers' sums into `next` in cell
/// order (clearing the landings for the next step), rescales the masses by `factor`, and sums
/// the L1 change against `image` on the new cells.
Settled settle(std::vector<Landing>& landings, const Cells& at, const MassImage& image, double factor, int threads,
               MassImage& next, const ProgressCallback& poll) {
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
  }, poll);
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
  }, poll);
  Settled all;
  for (const Settled& s : settled) {
    all.change += s.change;
    all.old_inside += s.old_inside;
    all.total += s.total;
  }
  return all;
}

}  // namespace
}  // namespace mass_transport_detail

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
  using namespace mass_transport_detail;  // in the function: a unity build's next file does not see it
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
  std::vector<float> centroid, color;  // per cell: where its mass sits in it, channel means
  TransportResult result;
  double reported = 0.0;
  for (result.iterations = 0; result.iterations < plan.max_iterations;) {
    // A step over 8000^2 cells takes seconds: its passes hear Ctrl-C (progress stays put).
    const ProgressCallback poll = progress_range(options.progress, reported, reported);
    const std::vector<std::uint32_t>& old_cells = image.cells;
    const bool box = at.position && ch == 0;  // transport_box decodes the centroids itself
    if (!at.by_component && !box) decode_records(at, image, codec, centroid, color);
    const Step step{space, plan, at, weight, codec, image, centroid, color, half};
    parallel_jobs((old_cells.size() + kChunk - 1) / kChunk, threads, [&](std::size_t job, int worker) {
      const std::size_t begin = job * kChunk, end = std::min(old_cells.size(), (job + 1) * kChunk);
      if (at.by_component)
        transport_rounded(step, begin, end, landings[worker]);
      else if (box)
        transport_box(step, begin, end, landings[worker]);
      else
        transport_spread(step, begin, end, landings[worker]);
    }, poll);
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
    const Settled settled = settle(landings, at, image, factor, threads, next, poll);
    // (From the start, a pseudo component, everything changes; it takes two steps to stop.)
    result.change = static_cast<double>(settled.change + (old_total - settled.old_inside)) / kUnit;
    old_total = settled.total;
    const bool support_changed = next.cells != image.cells;
    std::swap(image, next);
    ++result.iterations;
    reported = std::clamp(std::log(std::max(result.change, 1e-300)) / std::log(plan.threshold), 0.0, 1.0);
    report_progress(options, reported);
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
