#pragma once
/// @file The host side of the chain lanes (chaos_chains.h): a system's tables, its jobs' streams,
/// the kernel for this CPU, and each batch of points handed to a sink of the chaos game's.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "chaos_chains.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/render/accumulator.h"
#include "ifsforge/render/frame.h"

namespace ifsforge::chains {

/// Whether the general path runs its jobs in the chain lanes: yes unless IFSFORGE_CHAOS_CHAINS=0,
/// which tests and benchmarks use to compare them with the one-job reference loop (the same
/// bytes).
bool enabled();

/// The kernel IFSFORGE_ISA and the CPU pick (chaos_lanes.h's lane_isa).
Kernel kernel();

/// Jobs per task for `jobs` jobs on `threads` threads: as many chains as fill the lanes while
/// every thread still has a task.
std::uint64_t jobs_per_task(std::uint64_t jobs, int threads);

/// The chains of jobs [first, first + count) (count at most kMaxChains): the system's start
/// point, each job's own stream (seed, job) after MapChain::start, as the one-job loop draws
/// it; `points` points per chain after `skip` unplotted ones (where they go left unset).
Job start_chains(const Ifs& ifs, const MapChain& chain, std::uint64_t seed, std::uint64_t first, int count,
                 std::uint64_t points, std::uint64_t skip);

/// A system's maps and its chain's draws as the kernels take them (Maps' fields up to `direct`;
/// the frame's are left zero): the chaos game's Plan, and the random-iteration volume's lanes
/// (volume/voxel_chains.h), which find voxels instead of pixels.
class MapTables {
 public:
  MapTables(const Ifs& ifs, const MapChain& chain);
  MapTables(const MapTables&) = delete;  // maps_ points into the tables
  MapTables& operator=(const MapTables&) = delete;
  const Maps& maps() const { return maps_; }

 protected:
  std::vector<double> coefficients_;
  std::vector<std::uint64_t> choices_;
  std::vector<double> draws_;
  Maps maps_{};
  /// Every map's rows shrink the max norm and no offset is -0: zero terms may be left out.
  bool sparse_ = true;
};

/// One render's tables: the maps, the chain's draws, the frame's projection and the channels'
/// quantisation (the accumulator's).
class Plan : MapTables {
 public:
  Plan(const Ifs& ifs, const Frame& frame, const MapChain& chain, const Accumulator& accumulator);

  /// Jobs [first, first + count) (count at most kMaxChains): each draws `points` points after
  /// `skip` unplotted ones, exactly as the general path's one-job loop does, into `sink`: its
  /// add_batch(slots, levels, depths, n) (levels and depths as Job::flush has them), and
  /// counters() and counter_bytes(), where the kernel prefetches each pixel's counters; a 2D
  /// system of three channels' batches go to the sink's packed_records() instead, where it has
  /// them (Job::records).
  template <class Sink>
  void run(std::uint64_t first, int count, std::uint64_t points, std::uint64_t skip, std::uint64_t seed,
           const Sink& sink) const {
    run(first, count, points, skip, seed, &flush<Sink>, const_cast<Sink*>(&sink), sink.counters(),
        sink.counter_bytes(), sink.packed_records(), sink.packed_carry());
  }

 private:
  template <class Sink>
  static void flush(void* sink, const std::uint32_t* slots, const std::uint32_t* levels, const float* depths,
                    std::size_t n) {
    static_cast<const Sink*>(sink)->add_batch(slots, levels, depths, n);
  }
  using Flush = void (*)(void*, const std::uint32_t*, const std::uint32_t*, const float*, std::size_t);
  void run(std::uint64_t first, int count, std::uint64_t points, std::uint64_t skip, std::uint64_t seed, Flush flush,
           void* target, const void* counters, std::size_t counter_bytes, std::uint32_t* records,
           std::uint64_t* carry) const;

  const Ifs& ifs_;
  const MapChain& chain_;
};

}  // namespace ifsforge::chains
