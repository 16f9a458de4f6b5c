#include "ifsforge/render/color_stealing.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/render/accumulator.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {

Ifs grid_reference_system(std::size_t n) {
  // The rectangle R = [0, 1] x [0, r], r = 1/sqrt(N), cut into N vertical strips of width 1/N:
  // each strip is R turned a quarter and scaled by r, so map i (a similarity, factor r < 1 for
  // any N >= 2) sends R onto strip i and the attractor is all of R.
  const double count = static_cast<double>(std::max<std::size_t>(n, 1));
  const double r = n > 1 ? 1.0 / std::sqrt(count) : 0.5;
  std::vector<AffineMap> maps;
  for (std::size_t i = 0; i < n; ++i)
    maps.emplace_back(2, std::vector<double>{0, r, r, 0}, std::vector<double>{static_cast<double>(i) / count, 0});
  return Ifs("grid reference", ChannelLayout("xy"), maps, std::vector<double>(n, 1.0));
}

double grid_reference_height(std::size_t n) { return n > 1 ? 1.0 / std::sqrt(static_cast<double>(n)) : 0.5; }

Capabilities ColorStealing::capabilities() const {
  // The chaos game of 5.1.1 with the walker's maps; the reference system has no polar twin.
  using C = Capabilities;
  return {C::Recurrent | C::AverageContractive | C::Overlapping | C::Plane | C::Space};
}

Raster ColorStealing::draw(const Ifs& ifs, const RenderOptions& options) const {
  if (!options.reference_image || options.reference_image->width < 1)
    throw InputError("color stealing needs a reference image");
  const Image& picture = *options.reference_image;
  const Ifs reference = options.reference_system ? *options.reference_system
                                                 : grid_reference_system(ifs.size());
  // The picture covers the reference's unit square, or the default's rectangle.
  const double picture_height = options.reference_system ? 1.0 : grid_reference_height(ifs.size());
  if (reference.size() != ifs.size())
    throw InputError("the reference system has " + std::to_string(reference.size()) +
                     " maps but the system has " + std::to_string(ifs.size()) +
                     "; color stealing pairs them one to one");
  if (reference.dim() != 2) throw InputError("the reference system must be 2D (xy)");
  ifs.require_attractor();
  reference.require_attractor();
  const Frame frame = Frame::fit(ifs, options.width, options.height, options.window, options.view);
  const std::uint64_t total = options.iterations ? options.iterations
                                                 : default_iterations(options.width, options.height,
                                                                      true, 1.0);  // Eq. 47
  const int threads = resolve_threads(options.threads);
  check_memory(threads * Accumulator::bytes(frame.width(), frame.height(), false, 3),
               "a color-stealing image");
  std::vector<Accumulator> acc;
  for (int t = 0; t < threads; ++t)
    acc.emplace_back(frame.width(), frame.height(), false, std::vector<double>{0, 0, 0},
                     std::vector<double>{1, 1, 1});
  // The system's walk (its transitions, when recurrent) picks the maps; the reference applies
  // the same index, so the picture is walked by the paired maps.
  const MapChain chain(ifs);
  const std::uint64_t per_job = 1u << 20;
  const std::uint64_t jobs = (total + per_job - 1) / per_job;
  const std::size_t trash = std::size_t(frame.width()) * frame.height();
  parallel_jobs(
      jobs, threads,
      [&](std::size_t job, int worker) {
        Rng rng(options.seed, job);
        Point q = ifs.start_point(), r = reference.start_point(), t;
        std::uint32_t k = chain.start(rng);
        const std::uint64_t count = std::min(per_job, total - job * per_job);
        float color[4] = {0, 0, 0, 0};
        double rgb[kMaxDim] = {};  // sized for any channel count, silencing GCC
        for (std::uint64_t i = 0; i < count + options.skip; ++i) {
          k = chain.next(k, rng.next());
          ifs.map(k).apply(q.data(), t.data());
          q = t;
          reference.map(k).apply(r.data(), t.data());
          r = t;
          if (i < options.skip) continue;
          const auto px = frame.to_pixel(q);
          const bool inside = px[0] >= 0 && px[0] < frame.width() && px[1] >= 0 && px[1] < frame.height();
          picture.sample(r[0] * picture.width, (1.0 - r[1] / picture_height) * picture.height, color);
          for (int c = 0; c < 3; ++c) rgb[c] = color[picture.channels >= 3 ? c : 0];
          acc[worker].add(inside ? std::size_t(px[1]) * frame.width() + std::size_t(px[0]) : trash, rgb);
        }
      },
      options.progress);
  for (int t = 1; t < threads; ++t) acc[0].merge(acc[t]);
  Raster raster;
  acc[0].finish(raster);
  raster.channel_names = {"r", "g", "b"};
  raster.color_model = ColorModel::Rgb;
  raster.channels_in_unit_range = true;
  raster.points = total;
  return raster;
}

}  // namespace ifsforge
