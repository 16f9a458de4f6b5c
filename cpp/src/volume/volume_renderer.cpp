#include "ifsforge/volume/volume_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/named.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/recursion.h"
#include "ifsforge/volume/deterministic_iteration_volume.h"
#include "ifsforge/volume/escape_time_volume.h"
#include "ifsforge/volume/point_recursive_volume.h"
#include "ifsforge/volume/random_iteration_volume.h"

namespace ifsforge {
namespace {

struct Entry {
  std::unique_ptr<VolumeRenderer> renderer;
  std::vector<std::string> aliases;
};

const std::vector<Entry>& registry() {
  static const std::vector<Entry> entries = [] {
    std::vector<Entry> e;
    e.push_back({std::make_unique<PointRecursiveVolume>(), {"point-recursive"}});
    e.push_back({std::make_unique<RandomIterationVolume>(), {"random", "chaos"}});
    e.push_back({std::make_unique<DeterministicIterationVolume>(), {"deterministic"}});
    e.push_back({std::make_unique<EscapeTimeVolume>(), {"escape-time"}});
    return e;
  }();
  return entries;
}

}  // namespace

const VolumeRenderer& volume_renderer(const std::string& name) {
  return find_named(registry(), name, "volume algorithm");
}

std::vector<const VolumeRenderer*> volume_renderers() {
  std::vector<const VolumeRenderer*> out;
  for (const auto& entry : registry()) out.push_back(entry.renderer.get());
  return out;
}

std::string VolumeRenderer::draw_jobs(const Ifs&, const VolumeOptions&, std::uint64_t, std::uint64_t) const {
  throw InputError("the " + name() + " volume renderer does not split into independent jobs: distribute prr or ria");
}

const std::vector<std::pair<std::string, Capabilities>>& volume_renderer_capabilities() {
  static const std::vector<std::pair<std::string, Capabilities>> all = capability_table(registry());
  return all;
}

void VolumeRenderer::require_handles(const Ifs& ifs) const {
  ifsforge::require_handles("volume algorithm", name(), capabilities(), ifs, volume_renderer_capabilities());
}

Volume VolumeRenderer::render(const Ifs& ifs, const VolumeOptions& options) const {
  require_handles(ifs);
  return draw(ifs, options);
}

std::string VolumeRenderer::run_jobs(const Ifs& ifs, const VolumeOptions& options, std::uint64_t first,
                                     std::uint64_t last) const {
  require_handles(ifs);
  return draw_jobs(ifs, options, first, last);
}

Volume VolumeRenderer::render_bands(const Ifs& ifs, VolumeOptions options, const VolumeBandSink& sink) const {
  bool given = false;
  options.bands = [&](const Volume& header, std::size_t bands, const VolumeBandLoader& load) {
    given = true;
    sink(header, bands, load);
  };
  Volume volume = render(ifs, options);
  if (!given) {
    sink(volume, volume_bands(volume.grid), band_loader(volume));
    volume.keys = {};
    volume.density = {};
    volume.channels = {};
  }
  return volume;
}

Volume render_volume(const Ifs& ifs, const std::string& algorithm, const VolumeOptions& options) {
  return volume_renderer(algorithm).render(ifs, options);
}

double expected_voxels(const Ifs& ifs, const VolumeOptions& options, const VolumeSetup& setup,
                       double bytes_per_voxel, double fixed_bytes) {
  const double cells = setup.grid.cells();
  const double n = std::max<double>(2.0, static_cast<double>(ifs.size()));
  double shrink = 0.0;
  for (double s : ifs.spatial_contraction_factors()) shrink = std::max(shrink, s);
  const double dimension = shrink > 0.0 && shrink < 1.0 ? std::min(3.0, std::log(n) / -std::log(shrink)) : 3.0;
  const double res = options.resolution;
  const double bound = std::min(cells, 8.0 * std::pow(res, dimension));
  constexpr int kPilot = 64;
  if (bound * bytes_per_voxel + fixed_bytes <= static_cast<double>(memory_budget()) || options.resolution <= kPilot)
    return bound;
  // The pilots see the same box (the attractor's, or options.bounds) at two resolutions.
  VolumeOptions pilot;
  pilot.bounds = options.bounds;
  pilot.threads = options.threads;
  auto count = [&](int resolution) {
    pilot.resolution = resolution;
    try {
      return static_cast<double>(volume_renderer("prr").render(ifs, pilot).size());
    } catch (const InputError&) {  // a system PRR does not take
      return static_cast<double>(volume_renderer("ria").render(ifs, pilot).size());
    }
  };
  const double coarse = std::max(1.0, count(kPilot / 2)), fine = std::max(1.0, count(kPilot));
  const double slope = std::clamp(std::log2(fine / coarse), 0.0, 3.0);
  // A quarter more: the slope at 32-64 voxels is an estimate of the dimension, not its value.
  return std::min(bound, 1.25 * fine * std::pow(res / kPilot, slope));
}

namespace {

/// The points of `points` farthest along one of the 26 directions (dx, dy, dz) in
/// {-1, 0, 1}^3 \ 0, without repeats; ties go to the earlier point.
std::vector<Point> farthest_points(const std::vector<Point>& points) {
  std::vector<Point> out;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        if (!dx && !dy && !dz) continue;
        const Point* best = nullptr;
        double reach = -std::numeric_limits<double>::infinity();
        for (const Point& p : points) {
          const double r = dx * p[0] + dy * p[1] + dz * p[2];
          if (!best || r > reach + 1e-12 * (1.0 + std::abs(reach))) {
            reach = r;
            best = &p;
          }
        }
        if (best && std::find(out.begin(), out.end(), *best) == out.end()) out.push_back(*best);
      }
  return out;
}

}  // namespace

Bounds volume_bounds(const Ifs& ifs, std::vector<Point>* extremes, int threads) {
  const int n = ifs.dim();
  // For hyperbolic systems these include W^d of the fixed points (model/attractor_points.h),
  // which reach the tips of rarely chosen maps that sampling misses: fewer samples do (as for
  // images). Other systems rely on the samples alone.
  const bool hyperbolic = ifs.classify() == Classification::Hyperbolic;
  Bounds b = ifs.attractor_bounds(hyperbolic ? 1u << 16 : 1u << 18, threads);
  std::vector<Point> candidates;
  // Fixed points of contractive maps lie on the attractor (and, for most systems, at its
  // corners); a sample stands in when there are none.
  for (std::size_t i = 0; i < ifs.size(); ++i)
    if (ifs.map(i).contraction_factor() < 1.0)
      if (const auto f = ifs.map(i).fixed_point()) candidates.push_back(*f);
  if (extremes) {
    if (candidates.empty())
      sample_attractor(ifs, 4096, 0xE87, [&](const Point& p) {
        bool inside = true;
        for (int c = 0; c < n; ++c) inside = inside && p[c] >= b.lo[c] && p[c] <= b.hi[c];
        if (inside) candidates.push_back(p);
      });
    // Spread them over the attractor (images under the maps) while that keeps them few.
    while (!candidates.empty() && candidates.size() * ifs.size() <= 16) {
      std::vector<Point> images;
      for (const Point& p : candidates)
        for (const auto& m : ifs.maps()) {
          const Point q = m(p);
          if (std::find(images.begin(), images.end(), q) == images.end()) images.push_back(q);
        }
      candidates.swap(images);
    }
    *extremes = candidates.size() > 8 ? farthest_points(candidates) : candidates;
  }
  return b;
}

VolumeSetup prepare_volume(const Ifs& ifs, const VolumeOptions& options) {
  if (ifs.spatial_dims() != 3)
    throw InputError("a volume needs a 3D system (layout xyz, xyz+gray, xyz+rgb, xyz+hsi, ...); '" +
                     ifs.name() + "' has layout '" + ifs.layout().text() + "'");
  if (options.resolution < 1 || options.resolution > kMaxVolumeResolution)
    throw InputError("the volume resolution must be 1.." + std::to_string(kMaxVolumeResolution) +
                     " voxels per side, got " + std::to_string(options.resolution));
  ifs.require_attractor();
  VolumeSetup setup;
  setup.bounds = volume_bounds(ifs, &setup.extremes, resolve_threads(options.threads));
  const int n = ifs.dim();
  for (int c = 0; c < n; ++c) {
    if (!std::isfinite(setup.bounds.lo[c]) || !std::isfinite(setup.bounds.hi[c]))
      throw DivergentSystemError("system '" + ifs.name() + "' has unbounded channel '" +
                                 ifs.layout().names()[c] + "'");
  }
  // Any invariant box: a volume's pieces nest in it, and its occupancy tests find more of the
  // attractor's voxels (the 3D fern at 256^3 lost 128 of 19,718 in the grown bounds instead).
  piece_box(ifs, setup.bounds, 0.01, true, setup.center, setup.half);
  if (options.bounds) {
    setup.grid = fit_voxel_grid(*options.bounds, options.resolution);
  } else {
    // The attractor's box itself, cells aligned to its low corner: a grid-aligned fractal
    // (Menger sponge at 3^k) fills exactly its cells. A point attractor gets a tiny cube.
    Box3 box{};
    for (int a = 0; a < 3; ++a) {
      box[a] = setup.bounds.lo[a];
      box[a + 3] = setup.bounds.hi[a];
    }
    double longest = 0.0;
    for (int a = 0; a < 3; ++a) longest = std::max(longest, box[a + 3] - box[a]);
    if (!(longest > 0.0)) {
      const double pad = std::max(1e-9, 1e-9 * std::abs(box[0]));
      for (int a = 0; a < 3; ++a) box[a + 3] = box[a] + pad;
    }
    setup.grid = fit_voxel_grid(box, options.resolution);
  }
  setup.quantizer = ChannelQuantizer(std::vector<double>(setup.bounds.lo.begin() + 3, setup.bounds.lo.end()),
                                     std::vector<double>(setup.bounds.hi.begin() + 3, setup.bounds.hi.end()));
  setup.threads = resolve_threads(options.threads);
  return setup;
}

}  // namespace ifsforge
