#include "ifsforge/design/breed.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/random.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {
namespace {

constexpr double kMaxContraction = 0.9;  // every drawn map's s_i (Eq. 30) stays at most this

double between(Rng& rng, double lo, double hi) { return lo + (hi - lo) * rng.uniform(); }

/// One map of Eq. 32's family: mostly shrinking (f0 < 0), a few harmonics that shape the
/// radial factor around P, a turn and a spiral for G, a mirror now and then.
PolarMap draw_map(Rng& rng) {
  for (;;) {
    PolarMap m;
    m.center = {between(rng, -1.0, 1.0), between(rng, -1.0, 1.0)};
    m.k = between(rng, 0.6, 2.0);
    m.f[0] = between(rng, -1.2, 0.1);
    m.f[1] = between(rng, -0.6, 0.6);
    for (int i = 2; i < PolarMap::kF; ++i) m.f[i] = between(rng, -0.6, 0.6);
    m.g[0] = between(rng, -M_PI, M_PI);
    m.g[1] = between(rng, -1.5, 1.5);
    m.g[2] = between(rng, -0.4, 0.4);
    m.g[3] = between(rng, -0.4, 0.4);
    m.winding = rng.uniform() < 0.25 ? -1 : 1;
    if (m.contraction() <= kMaxContraction) return m;
  }
}

/// Whether `ifs` is worth a picture (see breed()).
bool acceptable(const Ifs& ifs, const BreedOptions& o) {
  double spread = 0.0;
  for (const auto& p : ifs.polar_maps())
    for (const auto& q : ifs.polar_maps())
      spread = std::max({spread, std::abs(p->center[0] - q->center[0]), std::abs(p->center[1] - q->center[1])});
  const Bounds b = ifs.attractor_bounds(1u << 14);
  const double extent = std::max(b.hi[0] - b.lo[0], b.hi[1] - b.lo[1]);
  if (!(extent >= o.min_extent * std::max(spread, 0.5))) return false;
  RenderOptions r;
  r.width = r.height = o.probe;
  r.binary = true;
  r.threads = 1;
  const Raster raster = renderer("chaos").render(ifs, r);
  const double share = static_cast<double>(raster.covered()) / (double(o.probe) * o.probe);
  return share >= o.min_coverage && share <= o.max_coverage;
}

}  // namespace

std::vector<Ifs> breed(const BreedOptions& o) {
  if (o.count < 1 || o.count > 4096) throw InputError("breed: count must be 1..4096");
  // One map's attractor is its centre (Eq. 30 pulls everything to P): two at least.
  if (o.maps < 0 || o.maps == 1 || o.maps > 16) throw InputError("breed: maps must be 0 (2 to 4, drawn) or 2..16");
  if (o.probe < 8 || o.probe > 1024) throw InputError("breed: probe must be 8..1024 pixels");
  if (!(o.min_coverage >= 0.0 && o.min_coverage < o.max_coverage && o.max_coverage <= 1.0))
    throw InputError("breed: expected 0 <= min_coverage < max_coverage <= 1");
  if (!(o.min_extent >= 0.0) || o.attempts < 1) throw InputError("breed: min_extent must be >= 0 and attempts >= 1");
  std::vector<Ifs> out;
  for (int k = 0; k < o.count; ++k) {
    Rng rng(o.seed, static_cast<std::uint64_t>(k));
    const std::string name = "phenotype " + std::to_string(k) + " (seed " + std::to_string(o.seed) + ")";
    bool found = false;
    for (int attempt = 0; attempt < o.attempts && !found; ++attempt) {
      const int n = o.maps > 0 ? o.maps : 2 + static_cast<int>(rng.next() % 3);
      std::vector<PolarMap> maps;
      for (int i = 0; i < n; ++i) maps.push_back(draw_map(rng));
      Ifs ifs = polar_ifs(name, maps);
      if (!acceptable(ifs, o)) continue;
      out.push_back(std::move(ifs));
      found = true;
    }
    if (!found)
      throw InputError("breed: phenotype " + std::to_string(k) + " found no acceptable draw in " +
                       std::to_string(o.attempts) + " attempts (loosen min_coverage, max_coverage or min_extent)");
  }
  return out;
}

}  // namespace ifsforge
