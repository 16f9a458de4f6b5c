#include <algorithm>

#include "ifsforge/core/random.h"
#include "polar_render.h"

namespace ifsforge::polar {

void chaos_job(const Ifs& ifs, const Frame& frame, const MapChain& chain, std::uint64_t points, std::uint64_t skip,
               std::uint64_t seed, std::uint64_t job, Accumulator& acc) {
  // Four orbits interleaved, each from its own stream (seed, 4 job + c): one orbit is a chain
  // of dependent exp and sincos (Eq. 32); independent ones overlap in the core's pipelines.
  constexpr int kChains = 4;
  const int n = ifs.dim();
  const auto& maps = ifs.maps();
  const auto& polar = ifs.polar_maps();
  const Point start = ifs.start_point();  // a centre P_i: fixed by its map, so on the attractor
  Rng rng[kChains] = {Rng(seed, job * kChains), Rng(seed, job * kChains + 1), Rng(seed, job * kChains + 2),
                      Rng(seed, job * kChains + 3)};
  Point p[kChains];
  std::uint32_t state[kChains];
  for (int c = 0; c < kChains; ++c) {
    p[c] = start;
    state[c] = chain.start(rng[c]);
  }
  auto step = [&](int c) {
    const std::size_t i = state[c] = chain.next(state[c], rng[c].next());
    Point q;
    maps[i].apply(p[c].data(), q.data());  // the channel rows (and the spatial ones of an affine map)
    if (polar[i]) polar[i]->apply(p[c].data(), q.data());
    std::copy(q.begin(), q.begin() + n, p[c].begin());
  };
  for (std::uint64_t i = 0; i < skip; ++i)
    for (int c = 0; c < kChains; ++c) step(c);
  const std::size_t trash = std::size_t(frame.width()) * frame.height();
  const double w = frame.width(), h = frame.height();
  const bool channels = n > 2;
  auto plot = [&](const Point& q) {
    const auto px = frame.to_pixel(q);
    const bool inside = px[0] >= 0.0 && px[0] < w && px[1] >= 0.0 && px[1] < h;
    acc.add(inside ? std::size_t(px[1]) * frame.width() + std::size_t(px[0]) : trash, channels ? q.data() + 2 : nullptr);
  };
  for (std::uint64_t i = 0; i < points / kChains; ++i)
    for (int c = 0; c < kChains; ++c) {
      step(c);
      plot(p[c]);
    }
  for (int c = 0; c < static_cast<int>(points % kChains); ++c) {
    step(c);
    plot(p[c]);
  }
}

}  // namespace ifsforge::polar
