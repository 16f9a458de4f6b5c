#include "ifsforge/core/random.h"
#include "polar_render.h"

namespace ifsforge::polar {

void chaos_job(const Ifs& ifs, const Frame& frame, const MapSampler& sampler, const std::vector<MapSampler>*,
               std::uint64_t points, std::uint64_t skip, std::uint64_t seed, std::uint64_t job, Accumulator& acc) {
  Rng rng(seed, job);
  Point p = ifs.start_point();  // a centre P_i: fixed by its map, so on the attractor
  for (std::uint64_t i = 0; i < skip; ++i) p = ifs.apply(sampler(rng.next()), p);
  const std::size_t trash = std::size_t(frame.width()) * frame.height();
  const double w = frame.width(), h = frame.height();
  const bool channels = ifs.dim() > 2;
  for (std::uint64_t i = 0; i < points; ++i) {
    p = ifs.apply(sampler(rng.next()), p);
    const auto px = frame.to_pixel(p);
    const bool inside = px[0] >= 0.0 && px[0] < w && px[1] >= 0.0 && px[1] < h;
    acc.add(inside ? std::size_t(px[1]) * frame.width() + std::size_t(px[0]) : trash, channels ? p.data() + 2 : nullptr);
  }
}

}  // namespace ifsforge::polar
