#pragma once
/// @file The chaos game's job loop (chaos_game.cpp sets a render up, picks its job functions and
/// finishes it): a render's jobs on the thread pool, each into its worker's accumulator or into
/// the workers' narrow counters (WorkerCounters), which then go into one accumulator or, for a 2D
/// lane render, to LaneHits (chaos_hits.h).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "ifsforge/core/memory.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/render/accumulator.h"
#include "ifsforge/render/frame.h"
#include "ifsforge/render/renderer.h"
#include "chaos_hits.h"
#include "chaos_lanes.h"
#include "chaos_sinks.h"
#include "chaos_tiles.h"

namespace ifsforge::workers {

struct JobPlan {
  std::uint64_t jobs, points_per_job;
};

/// What every job of one render shares: the frame, the point count and its cut into jobs.
struct ChaosSetup {
  Frame frame;
  JobPlan plan;
  std::vector<double> lo, hi;  // channel ranges
  bool simd = false;    // the lane kernels run the jobs
  bool narrow = false;  // the jobs count into narrow per-worker counters (every lane job does)
};

/// Whether a render's 2D lane counts go through tiles (chaos_tiles.h).
bool tiled_counts(bool simd, bool depth, std::size_t pixels);

/// A job's function (chaos_game.cpp's): `points` points after `skip`, from the stream (seed, job),
/// into a worker's accumulator, into its packed records (a 2D system with channels), or into its
/// narrow counters (a purely spatial system).
using ChaosJob = void (*)(const Ifs&, const Frame&, const MapChain&, std::uint64_t, std::uint64_t, std::uint64_t,
                          std::uint64_t, Accumulator&);
using ChannelJob = void (*)(const Ifs&, const Frame&, const MapChain&, std::uint64_t, std::uint64_t, std::uint64_t,
                            std::uint64_t, const sinks::ChannelSink&);
using NarrowJob = void (*)(const Ifs&, const Frame&, const MapChain&, std::uint64_t, std::uint64_t, std::uint64_t,
                           std::uint64_t, const sinks::NarrowSink&);
/// A lane job's start and streams (frame, n, start, points, skip, seed, job).
using LaneJob = lanes::Job (*)(const Frame&, int, const Point&, std::uint64_t, std::uint64_t, std::uint64_t,
                               std::uint64_t);

/// One render's job functions, by where the points go.
struct Jobs {
  ChaosJob scalar;      // a worker's accumulator (polar maps: their own path, 3.3.3)
  ChannelJob channel;   // packed records; null where the counters are not packed
  NarrowJob narrow;     // narrow counters, the general path's one-job loop
  // The lanes' (where setup.simd): their maps in pixel space, their kernel, each job's streams.
  lanes::Maps maps;
  lanes::Kernel kernel;
  LaneJob lane;
};

/// The workers' narrow counters (where setup.narrow), each worker's made at its first job: 8-bit
/// hits (32-bit hits beside depths in 3D; 32-bit hits and channel sums in 2D with channels,
/// "packed") flushed into the wide accumulator: when the jobs are done (the wraps went there
/// already), and also whenever a 32-bit hit counter could overflow. Large 2D images: each worker
/// bins its slots by tile and counts them tile by tile.
class WorkerCounters {
 public:
  /// Counters whose flushes and wraps go into `wide`, the one accumulator of a narrow render
  /// (unused otherwise: each worker then adds into an accumulator of its own).
  WorkerCounters(const Ifs& ifs, const ChaosSetup& setup, int threads, Accumulator& wide);
  /// Counters whose wraps go to `hits` (a 2D lane render's: no accumulator).
  WorkerCounters(const Ifs& ifs, const ChaosSetup& setup, int threads, sinks::LaneHits& hits);

  bool packed() const { return packed_; }
  /// Before a worker's task of `points` points: its counters, flushed first where a 32-bit one
  /// could overflow.
  void prepare(int worker, std::uint64_t points);
  sinks::ChannelSink channel_sink(int worker);
  sinks::NarrowSink narrow_sink(int worker);
  /// A lane job's slots through the worker's tiles, where the counts are tiled.
  void bin(int worker, lanes::Job& lane);
  /// What the bins still hold, each worker's on a core of its own.
  void drain();
  /// Everything into the wide accumulator.
  void total();
  /// The tiles' wraps and the 8-bit counters to `hits`.
  void hand_to(sinks::LaneHits& hits);

 private:
  WorkerCounters(const Ifs& ifs, const ChaosSetup& setup, int threads, Accumulator* wide, std::uint64_t* carry);
  void add_lane(int worker, std::size_t from, std::size_t to);
  void flush(int worker);

  Accumulator* wide_;
  std::uint64_t* carry_;  // where the 8-bit counters' wraps add 256
  int threads_;
  std::size_t pixels_;
  bool narrow_, depth_, packed_, tiled_;
  int channels_, stride_;
  std::vector<ZeroedVector<std::uint8_t>> lows_;
  std::vector<LargeVector<lanes::HitDepth>> cells_;
  std::vector<LargeVector<std::uint32_t>> records_;
  std::vector<std::uint64_t> pending_;
  std::mutex flushing_;
  std::vector<std::unique_ptr<lanes::TiledCounter>> tiles_;
  std::vector<std::vector<std::uint32_t>> batches_;
};

/// Runs jobs [first, last) on `threads` threads with `jobs`: each into its worker's accumulator
/// acc[worker] (a render without narrow counters), or into `counters`, the bins drained at the
/// end. acc[0] also gives the chain lanes their quantisation.
void run_jobs(const Ifs& ifs, const RenderOptions& options, const ChaosSetup& setup, const Jobs& jobs,
              std::uint64_t first, std::uint64_t last, int threads, std::vector<Accumulator>& acc,
              WorkerCounters& counters);

}  // namespace ifsforge::workers
