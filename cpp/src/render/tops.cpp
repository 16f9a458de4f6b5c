#include "ifsforge/render/tops.h"

#include <cmath>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/random.h"

namespace ifsforge {
namespace {

void check(const Ifs& ifs) {
  if (ifs.size() > 16) throw InputError("fractal tops keep 4 bits per address digit: system '" + ifs.name() +
                                        "' has " + std::to_string(ifs.size()) + " maps (at most 16)");
  if (ifs.spatial_dims() != 2)
    throw InputError("fractal tops are drawn on the plane; system '" + ifs.name() + "' is not planar");
  ifs.require_attractor();
}

std::vector<double> cumulative(const Ifs& ifs) {
  std::vector<double> c;
  double total = 0;
  for (double p : ifs.probabilities()) c.push_back(total += p);
  return c;
}

/// One chaos game on F and G with the same map choices (G = F for plain tops): per pixel of
/// G's frame, the largest address code and F's point that carried it.
template <typename Visit>
void chaos_pair(const Ifs& f, const Ifs& g, const TopsOptions& o, std::uint64_t points, Visit&& visit) {
  const auto cum = cumulative(f);
  Rng rng(o.seed, 0x7095);
  Point pf = f.start_point(), pg = g.start_point();
  std::uint64_t code = 0;
  for (std::uint64_t k = 0; k < points + 64; ++k) {
    const double u = rng.uniform() * cum.back();
    std::size_t i = 0;
    while (i + 1 < cum.size() && u >= cum[i]) ++i;
    pf = f.map(i)(pf);
    pg = g.map(i)(pg);
    // The map applied last is the outermost: it becomes the first digit (Eq. 35's address).
    code = (code >> 4) | (std::uint64_t(i) << 60);
    if (k >= 64 + kTopsDepth) visit(pf, pg, code);
  }
}

}  // namespace

Tops tops(const Ifs& ifs, const Frame& frame, const TopsOptions& o) {
  check(ifs);
  check_memory(9.0 * frame.width() * frame.height(), "a fractal-tops image");
  Tops t{frame.width(), frame.height(), std::vector<std::uint64_t>(std::size_t(frame.width()) * frame.height()),
         std::vector<std::uint8_t>(std::size_t(frame.width()) * frame.height())};
  const std::uint64_t points = o.iterations ? o.iterations : 16ull * t.width * t.height;
  chaos_pair(ifs, ifs, o, points, [&](const Point&, const Point& p, std::uint64_t code) {
    const auto px = frame.to_pixel(p);
    if (!(px[0] >= 0 && px[1] >= 0 && px[0] < t.width && px[1] < t.height)) return;
    const std::size_t c = std::size_t(px[1]) * t.width + std::size_t(px[0]);
    if (!t.covered[c] || code > t.codes[c]) t.codes[c] = code, t.covered[c] = 1;
  });
  return t;
}

Image tops_warp(const Ifs& f, const Frame& f_frame, const Image& picture, const Ifs& g, const Frame& g_frame,
                const TopsOptions& o) {
  check(f);
  check(g);
  if (f.size() != g.size())
    throw InputError("the warp needs systems with the same number of maps: '" + f.name() + "' has " +
                     std::to_string(f.size()) + ", '" + g.name() + "' " + std::to_string(g.size()));
  if (picture.width < 1 || picture.height < 1) throw InputError("the picture to warp is empty");
  const int w = g_frame.width(), h = g_frame.height();
  check_memory(41.0 * w * h, "a fractal-tops warp");
  std::vector<std::uint64_t> codes(std::size_t(w) * h);
  std::vector<std::uint8_t> covered(codes.size());
  std::vector<std::array<double, 2>> source(codes.size());
  const std::uint64_t points = o.iterations ? o.iterations : 16ull * w * h;
  chaos_pair(f, g, o, points, [&](const Point& pf, const Point& pg, std::uint64_t code) {
    const auto px = g_frame.to_pixel(pg);
    if (!(px[0] >= 0 && px[1] >= 0 && px[0] < w && px[1] < h)) return;
    const std::size_t c = std::size_t(px[1]) * w + std::size_t(px[0]);
    if (!covered[c] || code > codes[c]) codes[c] = code, covered[c] = 1, source[c] = f_frame.to_pixel(pf);
  });
  // The picture covers F's frame: its pixels scale onto the frame's.
  const double sx = double(picture.width) / f_frame.width(), sy = double(picture.height) / f_frame.height();
  Image out(w, h, 4);
  float rgba[4];
  for (std::size_t c = 0; c < codes.size(); ++c) {
    if (!covered[c]) continue;
    picture.sample(source[c][0] * sx, source[c][1] * sy, rgba);
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
