#include "chaos_chains_plan.h"

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "chaos_lanes.h"
#include "ifsforge/core/random.h"

namespace ifsforge::chains {

bool enabled() {
  const char* chains = std::getenv("IFSFORGE_CHAOS_CHAINS");
  return !(chains && std::strcmp(chains, "0") == 0);
}

Kernel kernel() {
  const char* isa = lanes::lane_isa();
  return std::strcmp(isa, "avx512") == 0 ? run_avx512 : std::strcmp(isa, "avx2") == 0 ? run_avx2 : run_baseline;
}

std::uint64_t jobs_per_task(std::uint64_t jobs, int threads) {
  const std::uint64_t share = (jobs + threads - 1) / threads;
  return std::clamp<std::uint64_t>(share, 1, kMaxChains);
}

Job start_chains(const Ifs& ifs, const MapChain& chain, std::uint64_t seed, std::uint64_t first, int count,
                 std::uint64_t points, std::uint64_t skip) {
  Job job{};
  job.chains = count;
  const Point start = ifs.start_point();
  for (int c = 0; c < ifs.dim(); ++c) job.start[c] = start[c];
  for (int k = 0; k < count; ++k) {
    Rng rng(seed, first + k);  // the job's own stream, as the one-job loop draws it
    job.map[k] = chain.start(rng);
    for (int w = 0; w < 4; ++w) job.rng[k][w] = rng.state()[w];
  }
  job.points = points;
  job.skip = skip;
  return job;
}

MapTables::MapTables(const Ifs& ifs, const MapChain& chain) {
  const int n = ifs.dim(), count = static_cast<int>(ifs.size()), spatial = ifs.spatial_dims();
  const int stride = (n * n + n + 3) / 4 * 4;  // whole registers of four doubles
  coefficients_.assign(std::size_t(count) * stride, 0.0);
  for (int i = 0; i < count; ++i) {
    double* row = coefficients_.data() + std::size_t(i) * stride;
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) row[r * n + c] = ifs.map(i).a(r, c);
      row[n * n + r] = ifs.map(i).b(r);
    }
  }
  // The chain's samplers, row by row (one row unless recurrent): the kernels draw as MapSampler.
  const int rows = chain.follows_transitions() ? count : 1;
  for (int row = 0; row < rows; ++row)
    for (int column = 0; column < count; ++column) {
      const MapSampler& sampler = chain.row(row);
      choices_.push_back(std::uint64_t(sampler.alias(column)) << 32 | sampler.threshold(column));
    }
  // Shared linear parts (the same bits): the offsets of both maps each draw may give, beside it.
  bool shared = true;
  for (int i = 1; i < count; ++i)
    shared = shared && std::memcmp(&coefficients_[std::size_t(i) * stride], &coefficients_[0], n * n * sizeof(double)) == 0;
  bool own_columns = true;
  for (std::size_t d = 0; d < choices_.size(); ++d) own_columns = own_columns && choices_[d] >> 32 == d % count;
  const bool direct = own_columns && n <= 3;  // the kernels' direct draws are 2D and 3D ones
  if (shared && count > kWidth && choices_.size() <= kMaxDraws) {
    const int row = direct ? offsets_row(n) : draw_row(n);
    draws_.assign(choices_.size() * row, 0.0);
    for (std::size_t d = 0; d < choices_.size(); ++d) {
      double* entry = &draws_[d * row];
      const std::size_t column = d % count, alias = choices_[d] >> 32;
      if (direct) {
        for (int r = 0; r < n; ++r) entry[r] = coefficients_[column * stride + n * n + r];
        continue;
      }
      std::memcpy(entry, &choices_[d], sizeof(double));
      for (int r = 0; r < n; ++r) {
        entry[1 + r] = coefficients_[column * stride + n * n + r];
        entry[1 + n + r] = coefficients_[alias * stride + n * n + r];
      }
    }
  }
  // Zero terms may be left out (Maps::diagonal, blocked, planar): every row of every map's a
  // sums to less than 1 in absolute value (each map shrinks the max norm, so from a finite start
  // no point overflows) and no b is -0.
  bool& sparse = sparse_;
  for (int i = 0; i < count; ++i)
    for (int r = 0; r < n; ++r) {
      const double* row = &coefficients_[std::size_t(i) * stride];
      double sum = 0.0;
      for (int c = 0; c < n; ++c) sum += std::fabs(row[r * n + c]);
      sparse = sparse && sum < 1.0 && !(row[n * n + r] == 0.0 && std::signbit(row[n * n + r]));
    }
  // A term is left out only where it is zero in every map's a.
  auto zero = [&](int r, int c) {
    for (int i = 0; i < count; ++i)
      if (coefficients_[std::size_t(i) * stride + r * n + c] != 0.0) return false;
    return true;
  };
  Maps& m = maps_;
  m.dim = n;
  m.spatial = spatial;
  m.count = count;
  m.recurrent = chain.follows_transitions();
  m.stride = stride;
  m.coefficients = coefficients_.data();
  m.choices = choices_.data();
  m.shared_linear = shared;
  m.diagonal = sparse;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) m.diagonal = m.diagonal && (r == c || zero(r, c));
  m.blocked = sparse && spatial < n;
  for (int r = 0; r < n; ++r)
    for (int c = spatial; c < n; ++c) m.blocked = m.blocked && (r == c || zero(r, c));
  m.by_height = m.blocked && spatial == 2;
  for (int r = spatial; r < n; ++r) m.by_height = m.by_height && zero(r, 0);
  m.draws = draws_.empty() ? nullptr : draws_.data();
  m.own_columns = own_columns;
  m.direct = direct;
}

Plan::Plan(const Ifs& ifs, const Frame& frame, const MapChain& chain, const Accumulator& accumulator)
    : MapTables(ifs, chain), ifs_(ifs), chain_(chain) {
  const int n = ifs.dim(), spatial = ifs.spatial_dims();
  const bool sparse = sparse_;
  Maps& m = maps_;
  // The general path's projection (chaos_game.cpp): the same doubles, the same zeros.
  const auto& proj = frame.projection();
  const double s = 1.0 / frame.pixel_size();
  for (int k = 0; k < spatial && k < 3; ++k) {
    m.u[k] = proj[0][k] * s;
    m.v[k] = -proj[1][k] * s;
  }
  m.planar = sparse && spatial == 2 && m.u[1] == 0.0 && m.v[0] == 0.0;
  m.u0 = -frame.window().xmin * s;
  m.v0 = frame.window().ymax * s;
  for (int k = 0; k < 3; ++k) m.toward[k] = frame.toward_viewer()[k];
  m.width = frame.width();
  m.height = frame.height();
  m.columns = static_cast<std::uint32_t>(frame.width());
  m.trash = static_cast<std::uint32_t>(std::uint64_t(frame.width()) * frame.height());
  for (int c = 0; c < n - spatial; ++c) {
    m.lo[c] = accumulator.channel_lo(c);
    m.scale[c] = accumulator.channel_scale(c);
  }
  m.steps = Accumulator::kChannelSteps;
}

void Plan::run(std::uint64_t first, int count, std::uint64_t points, std::uint64_t skip, std::uint64_t seed,
               Flush flush, void* target, const void* counters, std::size_t counter_bytes, std::uint32_t* records,
               std::uint64_t* carry) const {
  Job job = start_chains(ifs_, chain_, seed, first, count, points, skip);
  job.counters = static_cast<const char*>(counters);
  job.counter_bytes = counter_bytes;
  std::vector<std::uint32_t> slots(2 * kStride);
  std::vector<std::uint32_t> levels(2 * std::size_t(maps_.dim - maps_.spatial + 1) * kStride + 1);
  std::vector<float> depths(maps_.spatial == 3 ? 2 * kStride : 0);
  job.slots = slots.data();
  job.levels = levels.data();
  job.depths = depths.empty() ? nullptr : depths.data();
  job.flush = flush;
  job.sink = target;
  job.records = records;  // a 2D system of three channels' packed records, else null
  job.carry = carry;
  kernel()(maps_, job);
}

}  // namespace ifsforge::chains
