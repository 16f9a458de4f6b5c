#include "ifsforge/render/tops.h"

#include <array>
#include <cmath>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/model/orbit.h"

namespace ifsforge {
namespace {

void check(const Ifs& ifs) {
  if (ifs.size() > 16) throw InputError("fractal tops keep 4 bits per address digit: system '" + ifs.name() +
                                        "' has " + std::to_string(ifs.size()) + " maps (at most 16)");
  if (ifs.spatial_dims() != 2)
    throw InputError("fractal tops are drawn on the plane; system '" + ifs.name() + "' is not planar");
  ifs.require_attractor();
}

/// Pixels the walk missed inside the support (kTopsFillNeighbours of their 8 neighbours hit) take
/// their neighbours' top address, the largest, and its source.
void fill_pinholes(Tops& t, std::vector<std::array<double, 2>>* source) {
  const int w = t.width, h = t.height;
  const std::vector<std::uint8_t> hit = t.covered;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const std::size_t c = std::size_t(y) * w + x;
      if (hit[c]) continue;
      int around = 0;
      std::size_t top = c;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::size_t n = std::size_t(y + dy) * w + (x + dx);
          if (n == c || !hit[n]) continue;
          ++around;
          if (top == c || t.codes[n] > t.codes[top]) top = n;
        }
      if (around < kTopsFillNeighbours) continue;
      t.codes[c] = t.codes[top], t.covered[c] = 1;
      if (source) (*source)[c] = (*source)[top];
    }
}

/// The tops of G's frame and, per pixel, the point of F that carried the top address.
struct PairedTops {
  Tops tops;
  std::vector<std::array<double, 2>> source;  ///< F's frame pixel of each covered pixel
};

/// One chaos game on G (the system whose frame is drawn) with G's own probabilities or
/// transitions (MapChain), F's point following the same maps (F = G for plain tops): per pixel
/// of G's frame, the largest address code and F's point that carried it. The address is what
/// the two share, not the measure: G's attractor is covered as its own chaos game covers it,
/// whatever F's probabilities. With options.iterations 0, rounds of kTopsPointsPerPixel points
/// per pixel follow one another while a round still finds a share kTopsNewPixels of new
/// pixels (at most kTopsRounds).
PairedTops chaos_pair(const Ifs& f, const Frame& f_frame, const Ifs& g, const Frame& g_frame, const TopsOptions& o) {
  const int w = g_frame.width(), h = g_frame.height();
  PairedTops out{Tops{w, h, std::vector<std::uint64_t>(std::size_t(w) * h), std::vector<std::uint8_t>(std::size_t(w) * h), 0},
                 std::vector<std::array<double, 2>>(std::size_t(w) * h)};
  Tops& t = out.tops;
  // The first round walks G's own measure; later ones alternate with a spread one (Eq. 46's
  // probabilities, uniform for polar maps) that reaches where G's measure is thin. Any walk
  // finds top addresses: the probabilities only decide which points it visits. A recurrent
  // system keeps its transitions, or the walk would leave the attractor.
  const MapChain own(g);
  const MapChain spread = g.recurrent() ? own
                          : g.polar()   ? MapChain(std::vector<double>(g.size(), 1.0))
                                        : MapChain(jacobian_probabilities(g.maps(), 2));
  Rng rng(o.seed, 0x7095);
  std::uint32_t map = own.start(rng);
  Point pg = g.start_point(), pf = f.start_point();
  std::uint64_t code = 0;
  auto step = [&](const MapChain& chain) {
    map = chain.next(map, rng.next());
    pg = g.apply(map, pg);
    pf = f.apply(map, pf);
    // The map applied last is the outermost: it becomes the first digit (Eq. 35's address).
    code = (code >> 4) | (std::uint64_t(map) << 60);
  };
  // Burn-in: onto the attractor, and a full address of kTopsDepth digits.
  for (int k = 0; k < 64 + kTopsDepth; ++k) step(own);
  const std::uint64_t round = o.iterations ? o.iterations : std::uint64_t(kTopsPointsPerPixel) * w * h;
  std::size_t covered = 0;
  for (int r = 0; r < (o.iterations ? 1 : kTopsRounds); ++r) {
    const MapChain& chain = r % 2 ? spread : own;
    std::size_t found = 0;
    for (std::uint64_t k = 0; k < round; ++k) {
      step(chain);
      const auto px = g_frame.to_pixel(pg);
      if (!(px[0] >= 0 && px[1] >= 0 && px[0] < w && px[1] < h)) continue;
      const std::size_t c = std::size_t(px[1]) * w + std::size_t(px[0]);
      if (t.covered[c] && code <= t.codes[c]) continue;
      found += !t.covered[c];
      t.codes[c] = code, t.covered[c] = 1, out.source[c] = f_frame.to_pixel(pf);
    }
    for (double v : pg)
      if (!std::isfinite(v)) throw DivergentSystemError("system '" + g.name() + "' escapes to infinity under iteration");
    t.points += round;
    covered += found;
    if (r > 0 && double(found) <= kTopsNewPixels * double(covered)) break;
  }
  fill_pinholes(out.tops, &out.source);
  return out;
}

}  // namespace

Tops tops(const Ifs& ifs, const Frame& frame, const TopsOptions& o) {
  check(ifs);
  check_memory(25.0 * frame.width() * frame.height(), "a fractal-tops image");
  return chaos_pair(ifs, frame, ifs, frame, o).tops;
}

Image tops_warp(const Ifs& f, const Frame& f_frame, const Image& picture, const Ifs& g, const Frame& g_frame,
                const TopsOptions& o, std::uint64_t* points) {
  check(f);
  check(g);
  if (f.size() != g.size())
    throw InputError("the warp needs systems with the same number of maps: '" + f.name() + "' has " +
                     std::to_string(f.size()) + ", '" + g.name() + "' " + std::to_string(g.size()));
  if (picture.width < 1 || picture.height < 1) throw InputError("the picture to warp is empty");
  const int w = g_frame.width(), h = g_frame.height();
  check_memory(41.0 * w * h, "a fractal-tops warp");
  const PairedTops pair = chaos_pair(f, f_frame, g, g_frame, o);
  if (points) *points = pair.tops.points;
  // The picture covers F's frame: its pixels scale onto the frame's.
  const double sx = double(picture.width) / f_frame.width(), sy = double(picture.height) / f_frame.height();
  Image out(w, h, 4);
  float rgba[4];
  for (std::size_t c = 0; c < pair.tops.covered.size(); ++c) {
    if (!pair.tops.covered[c]) continue;
    picture.sample(pair.source[c][0] * sx, pair.source[c][1] * sy, rgba);
    float* o4 = &out.pixels[c * 4];
    if (picture.channels >= 3) {
      o4[0] = rgba[0], o4[1] = rgba[1], o4[2] = rgba[2];
    } else {
      o4[0] = o4[1] = o4[2] = rgba[0];
    }
    o4[3] = picture.channels == 2 || picture.channels == 4 ? rgba[picture.channels - 1] : 1.0f;
  }
  return out;
}

}  // namespace ifsforge
