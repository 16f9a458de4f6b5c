#pragma once
// Point recursive rendering's per-job results (private to render/): the leaves a job plots,
// the pixels it has covered, the node counts that decide the fallback, and their bytes for
// a cluster.
#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace ifsforge::prr {

/// The pixels one job has covered, over its root piece's pixel box: for coverage (binary) a
/// piece whose pixels are all covered already adds nothing below it. Overlapping systems (a
/// fern, the superfractal pair's union of two trees) revisit their pixels many times over.
class JobCoverage {
 public:
  /// Starts empty over the pixels [x0, x1) x [y0, y1) (clipped to the image by the caller).
  void reset(std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1) {
    x0_ = x0;
    y0_ = y0;
    width_ = std::max<std::int64_t>(x1 - x0, 0);
    height_ = std::max<std::int64_t>(y1 - y0, 0);
    words_ = (width_ + 63) / 64;
    bits_.assign(static_cast<std::size_t>(words_ * height_), 0);
  }

  void set(std::int64_t x, std::int64_t y) {
    x -= x0_;
    y -= y0_;
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    bits_[static_cast<std::size_t>(y * words_ + x / 64)] |= std::uint64_t(1) << (x % 64);
  }

  /// True when every pixel of [x0, x1] x [y0, y1] (inclusive) is covered; false for a range
  /// reaching outside the job's box.
  bool all(std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1) const {
    x0 -= x0_;
    x1 -= x0_;
    y0 -= y0_;
    y1 -= y0_;
    if (x0 < 0 || y0 < 0 || x1 >= width_ || y1 >= height_ || x1 < x0 || y1 < y0) return false;
    for (std::int64_t y = y0; y <= y1; ++y) {
      const std::uint64_t* row = bits_.data() + y * words_;
      for (std::int64_t x = x0; x <= x1;) {
        const std::int64_t end = std::min(x1, x - x % 64 + 63);
        const int from = static_cast<int>(x % 64), count = static_cast<int>(end - x + 1);
        const std::uint64_t want = count == 64 ? ~std::uint64_t(0) : ((std::uint64_t(1) << count) - 1) << from;
        if ((row[x / 64] & want) != want) return false;
        x = end + 1;
      }
    }
    return true;
  }

 private:
  std::int64_t x0_ = 0, y0_ = 0, width_ = 0, height_ = 0, words_ = 0;
  std::vector<std::uint64_t> bits_;
};

/// The leaves of one job that land on the image, in the walk's order, those that came to one
/// pixel close together summed into one entry (PixelSums).
struct LeafList {
  std::vector<std::uint32_t> pixel;
  std::vector<std::uint32_t> leaves;  // how many leaves the entry sums (the raster's points)
  std::vector<float> mass;            // their mass, summed in double, as the raster adds it
  std::vector<double> channels;       // their channel values' sums, pixel-major
  std::vector<float> depth;           // 3D systems: the nearest
  JobCoverage covered;                // binary renders only

  void clear() {
    pixel.clear();
    leaves.clear();
    mass.clear();
    channels.clear();
    depth.clear();
  }
};

/// A job's latest pixels and their sums, direct-mapped on the pixel's position modulo 32 x 32
/// (a neighbourhood stays in the L1 cache): leaves landing on a pixel the job reached a moment
/// ago (siblings, the pixels a small piece straddles) add to its entry, which goes to the list
/// when another pixel takes its slot, or at the job's end. A fern's job puts 26 leaves on each
/// pixel it covers, which the raster (or a cluster's driver) would otherwise add one by one.
/// What is summed depends on the job's walk alone: the same for any thread count or worker.
class alignas(64) PixelSums {  // one per thread: apart from its neighbour's cache line
 public:
  PixelSums(int channels, bool depth) : channels_(channels), depth_(depth) {
    sums_.resize(std::size_t(kSlots) * channels);
  }

  /// A leaf at pixel (x, y) (index `pixel`) with its mass, depth and `channels` values.
  void add(LeafList& list, std::size_t x, std::size_t y, std::uint32_t pixel, double mass, float depth,
           const double* values) {
    const std::size_t s = (x & 31) | (y & 31) << 5;
    Slot& slot = slots_[s];
    if (slot.pixel != pixel) {
      if (slot.pixel != kEmpty) flush(list, s);
      slot = {pixel, 0, 0.0};
      if (depth_) nearest_[s] = -std::numeric_limits<float>::infinity();
      if (channels_) std::fill(sums_.begin() + s * channels_, sums_.begin() + (s + 1) * channels_, 0.0);
    }
    ++slot.leaves;
    slot.mass += mass;
    if (depth_) nearest_[s] = std::max(nearest_[s], depth);
    for (int c = 0; c < channels_; ++c) sums_[std::size_t(s) * channels_ + c] += values[c];
  }

  /// Every entry to `list`, in slot order, leaving the table empty: at the job's end.
  void flush(LeafList& list) {
    for (std::size_t s = 0; s < kSlots; ++s)
      if (slots_[s].pixel != kEmpty) {
        flush(list, s);
        slots_[s].pixel = kEmpty;
      }
  }

 private:
  static constexpr std::size_t kSlots = 32 * 32;
  static constexpr std::uint32_t kEmpty = ~std::uint32_t(0);  // no image has 2^32 pixels
  struct Slot {
    std::uint32_t pixel = kEmpty, leaves = 0;
    double mass = 0.0;
  };
  void flush(LeafList& list, std::size_t s) const {
    list.pixel.push_back(slots_[s].pixel);
    list.leaves.push_back(slots_[s].leaves);
    list.mass.push_back(static_cast<float>(slots_[s].mass));
    if (depth_) list.depth.push_back(nearest_[s]);
    if (channels_)
      list.channels.insert(list.channels.end(), sums_.begin() + s * channels_, sums_.begin() + (s + 1) * channels_);
  }
  int channels_;
  bool depth_;
  std::array<Slot, kSlots> slots_;
  std::array<float, kSlots> nearest_;
  std::vector<double> sums_;
};

/// Thrown when a group of jobs exceeds its node budget: render() falls back to a fixed depth.
struct OverBudget {};

/// Nodes walked per group (the address prefixes of length RecursionPlan::prefix, N^prefix of
/// them), summed over the jobs below each: the totals, so whether one exceeds its budget,
/// are the same for any thread count, or split of the jobs among cluster workers.
class NodeCounts {
 public:
  NodeCounts(std::size_t groups, std::uint64_t budget) : counts_(groups), budget_(budget) {}
  /// Adds `nodes` to `group`; OverBudget once its total exceeds the budget.
  void add(std::uint64_t group, std::uint64_t nodes) {
    if (counts_[group].fetch_add(nodes) + nodes > budget_) throw OverBudget{};
  }
  std::size_t groups() const { return counts_.size(); }
  std::uint64_t count(std::size_t group) const { return counts_[group].load(); }

 private:
  std::vector<std::atomic<std::uint64_t>> counts_;
  std::uint64_t budget_;
};

/// Jobs' leaves for a cluster: a flag (1: a group was over budget), the groups' node counts
/// (how many, then group and count for each counted one), then per entry its pixel (the zigzag
/// of its step from the last), its leaves, its mass and depth as float bits and its channel
/// sums as double bits, all varints, in job order.
std::string encode_leaves(const std::vector<LeafList>& lists, bool over_budget, const NodeCounts& counts,
                          int channels);

/// The entries encode_leaves wrote, appended to one list (in job order), their node counts
/// added to `counts`; OverBudget when a group was, or now is, over budget.
void decode_leaves(std::string_view bytes, bool depth, int channels, std::size_t pixels, LeafList& list,
                   NodeCounts& counts);

}  // namespace ifsforge::prr
