#pragma once
/// @file The chaos game's lane kernels (seed 5.1.1): 4 groups of 8 chaos games at once in
/// single precision, iterating in pixel space. One kernel per instruction set, each in its own
/// translation unit compiled for that set (chaos_lanes_avx2.cpp: AVX2 + FMA; chaos_lanes_baseline.cpp:
/// any x86-64), chosen at run time (lane_kernel). They compute the same arithmetic, fused
/// multiply-adds included, so the image does not depend on the CPU. This header holds plain data
/// only: the per-ISA units include nothing else of the library, so no inline function of ours is
/// ever compiled for a wider instruction set than the one that runs it.
#include <cstddef>
#include <cstdint>

namespace ifsforge::lanes {

constexpr int kWidth = 8;   ///< lanes per group (one AVX2 register of floats)
constexpr int kGroups = 4;  ///< independent groups in flight, to hide FMA latency
constexpr std::uint64_t kLanes = kWidth * kGroups;

/// A 3D pixel's hits beside its largest depth: one cache line per point, not two.
struct HitDepth {
  std::uint32_t hits;
  float depth;
};

/// Up to 8 maps in pixel space (N = 2), or in pixel space plus depth towards the viewer (N = 3):
/// map i's coefficients in lane i.
struct Maps {
  alignas(32) float a[9][kWidth];  ///< a[r * N + c]
  alignas(32) float b[3][kWidth];
  alignas(32) std::int32_t thresholds[7];  ///< cumulative probability * 2^24, minus 1
  int count;
};

/// One job: where the lanes start, their xoshiro128+ states, the points and the counters.
struct Job {
  float origin[3];
  alignas(32) std::uint32_t state[kGroups][4][kWidth];
  std::uint64_t points, skip;  ///< points: a multiple of kLanes
  int width, height;           ///< the trash slot is width * height
  std::uint8_t* low;           ///< 2D: 8-bit hits, each wrap adding 256 to `carry` (atomically)
  std::uint64_t* carry;
  HitDepth* cells;             ///< 3D
  /// 2D, set: the slots go in batches of `batch_size` (a multiple of kLanes) to `flush(sink,
  /// slots, n)` instead of into `low` (tiled accumulation, chaos_tiles.h).
  std::uint32_t* batch;
  std::size_t batch_size;
  void (*flush)(void* sink, const std::uint32_t* slots, std::size_t n);
  void* sink;
};

using Kernel = void (*)(const Maps&, const Job&);

/// The kernels of each instruction set for N = 2 and N = 3.
void run_baseline2(const Maps&, const Job&);
void run_baseline3(const Maps&, const Job&);
void run_avx2_2(const Maps&, const Job&);
void run_avx2_3(const Maps&, const Job&);

/// The kernel for dimension `n` (2 or 3) on this CPU: AVX2 + FMA where the CPU has them, else
/// the baseline one. IFSFORGE_ISA=baseline (or avx2 or avx512, where supported) forces one; it is
/// read at each call, so a test can render with each in one process.
Kernel lane_kernel(int n);

/// The instruction set the kernels take now: "avx512" (the chain lanes' AVX-512 kernel, the float
/// lanes' AVX2 one), "avx2" or "baseline".
const char* lane_isa();

/// Whether a large 2D image is counted through tiles (chaos_tiles.h): yes unless
/// IFSFORGE_CHAOS_TILES=0, which benchmarks and tests use to compare the two (the same bytes).
bool lane_tiles();

/// Whether the general path counts a purely spatial system into the lanes' narrow counters: yes
/// unless IFSFORGE_CHAOS_NARROW=0, which tests and benchmarks use to compare them with a wide
/// accumulator per worker (the same bytes).
bool narrow_counters();

}  // namespace ifsforge::lanes
