#pragma once
/// @file The chaos game's chain lanes (seed 5.1.1): the general path's double-precision
/// walk, one job's chain per lane, up to 8 jobs at once. Each lane draws from its job's own
/// xoshiro256+ stream and MapChain (recurrent rows included, 3.3.1), applies the map with the
/// general path's operations in its order (no fused multiply-add), and projects the point the
/// way that path does, so every point, and the image, is that path's bit for bit whatever the
/// instruction set. One kernel per instruction set, each in its own translation unit
/// (chaos_chains_avx512.cpp and chaos_chains_avx2.cpp, one source for both widths:
/// chaos_chains_kernel.h; chaos_chains_baseline.cpp); like chaos_lanes.h this header holds
/// plain data only, so nothing of ours is compiled for a wider set than the one that runs it.
/// The lanes also quantise each point's channels as Accumulator::quantised does and round its
/// depth to float as Accumulator::add_depth does (the same operations: the same integers and
/// floats), so that a batch reaches the sink as integers and floats only.
#include <cstddef>
#include <cstdint>

namespace ifsforge::chains {

constexpr int kMaxDim = 8;     ///< the general path's largest dimension
constexpr int kWidth = 4;      ///< doubles per AVX2 register (Plan's tables: rows of four)
constexpr int kMaxChains = 8;  ///< jobs in flight: two AVX2 registers, to hide the map's latency; one AVX-512 one
/// Points per batch; a buffer holds kMaxChains more (a step's stores run past). Two buffers
/// alternate: a batch goes to the sink once the next one is full, so its counters, asked for
/// as each point was made, have arrived (a large image's counters miss the caches).
constexpr std::size_t kBatch = 32;
constexpr std::size_t kStride = kBatch + kMaxChains;
/// Doubles per row of Maps::draws: the choice, two offsets of `dim`, in whole registers of four.
constexpr int draw_row(int dim) { return (1 + 2 * dim + 3) / 4 * 4; }
/// Doubles per row of Maps::draws where Maps::direct: the column's b (2D: as one 128-bit half of
/// a register), else in whole registers of four.
constexpr int offsets_row(int dim) { return dim == 2 ? 2 : (dim + 3) / 4 * 4; }
/// Draws (rows times columns) up to which Plan builds Maps::draws (a recurrent system's table
/// grows with the square of its maps).
constexpr std::size_t kMaxDraws = std::size_t(1) << 16;

/// A system's maps and the frame's projection, as the general path (chaos_game.cpp) uses them.
struct Maps {
  int dim, spatial, count;
  bool recurrent;
  int stride;                    ///< doubles per map in `coefficients`: dim * dim + dim, padded with zeros to a multiple of 4
  const double* coefficients;    ///< map i at i * stride: a row by row, then b
  const std::uint64_t* choices;  ///< [row * count + column]: alias << 32 | threshold (MapSampler)
  bool shared_linear;            ///< every map's a has the same bits: only the offsets b differ
  /// Every map's a is diagonal and its zero terms may be left out of b + a x (Plan: no offset is
  /// -0 and every map's a shrinks the max norm, so every point is finite and no partial sum is
  /// -0; adding a zero term, 0 x, a zero of either sign, to it then changes no bit).
  bool diagonal;
  /// Every map's zero terms may be left out (as for `diagonal`), and its other terms lie in
  /// blocks: a spatial row's over the spatial columns, a channel row's over the spatial columns
  /// and its own (a colour system's channels: their own scale plus a geometric term), so that
  /// b + a x takes those terms only, in the general path's order.
  bool blocked;
  /// Blocked with 2 spatial coordinates, and no channel row takes x: every map's a[r][0] is 0
  /// for r >= 2 (colour that varies with height only, or not with the point at all).
  bool by_height;
  /// Shared linear parts and more than kWidth maps, else null: per draw (row * count + column) a
  /// row of draw_row(dim) doubles: the choice's bits, column's b, then its alias's b (zero-padded),
  /// so that one row per lane gives both the map and its offsets, without a gather.
  const double* draws;
  /// Every draw keeps its column (every alias is its own column: equal probabilities): the
  /// column is the map, whichever side of the threshold the draw falls (no choice is read).
  bool own_columns;
  /// 2D and 3D systems with own_columns: a row of `draws` is offsets_row(dim) doubles, the
  /// column's b only (no choice, no alias, no blend).
  bool direct;
  /// px = u0 + u . x, py = v0 + v . x over min(dim, 3) terms (zero past the spatial ones), and
  /// the depth toward . x in 3D.
  double u[3], v[3], u0, v0, toward[3];
  /// Zero terms may be left out (as for `diagonal`) and px = u0 + u[0] x0, py = v0 + v[1] x1 (a
  /// plane seen straight on): they change at most the sign of a zero px or py, which neither the
  /// bounds nor the pixel see.
  bool planar;
  double width, height;
  std::uint32_t columns, trash;  ///< the image's width in pixels; the slot of points off it
  /// Channel c's level: (x - lo[c]) * scale[c] clamped to [0, steps], plus 0.5, truncated.
  double lo[kMaxDim], scale[kMaxDim], steps;
};

/// Up to kMaxChains jobs: each chain's start, stream state and current map; the points per
/// chain; where the points go.
struct Job {
  int chains;
  double start[kMaxDim];
  std::uint64_t rng[kMaxChains][4];  ///< xoshiro256+ (core/random.h), after MapChain::start
  std::uint32_t map[kMaxChains];     ///< MapChain::start's state
  std::uint64_t points, skip;
  /// Where a slot's counters are: counters + slot * counter_bytes (prefetched, never written).
  const char* counters;
  std::size_t counter_bytes;
  std::uint32_t* slots;   ///< 2 * kStride slots: buffer b at b * kStride
  /// 2 * (channels + 1) * kStride levels: channel c of buffer b's point i at (b * (channels + 1) + c) * kStride + i
  /// (where `records`, the vector kernels' buffer b holds point i's record word at b * 4 * kStride + 4 i).
  std::uint32_t* levels;
  float* depths;  ///< 3D: 2 * kStride depths, buffer b at b * kStride
  /// Receives each batch: the points' slots, levels (channel c's at c * kStride) and depths,
  /// chain 0's point first in each step.
  void (*flush)(void* sink, const std::uint32_t* slots, const std::uint32_t* levels, const float* depths,
                std::size_t n);
  void* sink;
  /// A 2D system with three channels (ChannelSink's packed records: per pixel four 32-bit words,
  /// its hits and its channels' sums), else null: the kernel adds each batch to the records
  /// itself (ToRecords), in its own instruction set and without `flush`, and a sum below the
  /// level it took wrapped: 2^32 to carry[pixel * 3 + c], as ChannelSink::add_levels does.
  std::uint32_t* records;
  std::uint64_t* carry;
};

namespace {  // internal linkage: each kernel's unit compiles its own copy for its own set

/// Where a batch goes: the job's sink (Job::flush).
struct ToSink {
  static void add(const Job& job, const std::uint32_t* slots, const std::uint32_t* levels, const float* depths,
                  std::size_t n) {
    job.flush(job.sink, slots, levels, depths, n);
  }
};

/// The two alternating batch buffers of a job, each batch handed to Add::add (ToSink, or a
/// kernel's own add of Job::records).
template <class Add = ToSink>
class Batches {
 public:
  Batches(const Job& job, int channels) : job_(job), channels_(channels) {}
  std::uint32_t* slots() const { return job_.slots + buffer_ * kStride; }
  std::uint32_t* levels() const { return levels(buffer_); }
  float* depths() const { return depths(buffer_); }
  std::size_t filled() const { return filled_; }
  /// After a step of `chains` points: the other buffer to the sink once this one is full.
  void advance(int chains) {
    if ((filled_ += chains) + kMaxChains <= kBatch) return;
    send_other();
    waiting_ = filled_;
    filled_ = 0;
    buffer_ ^= 1;
  }
  void finish() {
    send_other();
    waiting_ = 0;
    if (filled_) Add::add(job_, slots(), levels(), depths(), filled_);
  }

 private:
  std::uint32_t* levels(int buffer) const { return job_.levels + std::size_t(buffer) * (channels_ + 1) * kStride; }
  float* depths(int buffer) const { return job_.depths ? job_.depths + buffer * kStride : nullptr; }
  void send_other() const {
    if (!waiting_) return;
    const int other = buffer_ ^ 1;
    Add::add(job_, job_.slots + other * kStride, levels(other), depths(other), waiting_);
  }
  const Job& job_;
  int channels_;
  int buffer_ = 0;
  std::size_t filled_ = 0, waiting_ = 0;
};

}  // namespace

using Kernel = void (*)(const Maps&, const Job&);

void run_baseline(const Maps&, const Job&);
void run_avx2(const Maps&, const Job&);
void run_avx512(const Maps&, const Job&);

}  // namespace ifsforge::chains
