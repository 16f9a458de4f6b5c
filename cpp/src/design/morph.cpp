#include "ifsforge/design/morph.h"

#include <cmath>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/model/map_params.h"

namespace ifsforge {
namespace {

double lerp(double a, double b, double t) { return a + (b - a) * t; }

/// Degrees, along the shorter arc (std::remainder gives the difference in [-180, 180]).
double lerp_angle(double a, double b, double t) { return a + std::remainder(b - a, 360.0) * t; }

AffineMap morph_map(const AffineMap& a, const AffineMap& b, int spatial, double t) {
  // The end points are returned as they are: the parameter round trip is exact only to
  // rounding, and a morph should start and end on its systems.
  if (t == 0.0) return a;
  if (t == 1.0) return b;
  const int n = a.dim();
  AffineMap out(n);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) out.a(r, c) = lerp(a.a(r, c), b.a(r, c), t);
    out.b(r) = lerp(a.b(r), b.b(r), t);
  }
  const MapParams pa = params_from_map(a, spatial), pb = params_from_map(b, spatial);
  MapParams p;
  p.dim = spatial;
  double sign[3];
  for (int c = 0; c < 3; ++c) {
    p.scale[c] = lerp(pa.scale[c], pb.scale[c], t);
    p.rotation[c] = lerp_angle(pa.rotation[c], pb.rotation[c], t);
    p.shear[c] = lerp(pa.shear[c], pb.shear[c], t);
    p.translation[c] = lerp(pa.translation[c], pb.translation[c], t);
    // A reflection cannot switch continuously; a signed factor from +1 to -1 can.
    sign[c] = lerp(pa.reflect[c] ? -1.0 : 1.0, pb.reflect[c] ? -1.0 : 1.0, t);
  }
  const AffineMap s = map_from_params(p);
  for (int r = 0; r < spatial; ++r) {
    // F = diag(sign) is the rightmost factor of A, so it scales the columns.
    for (int c = 0; c < spatial; ++c) out.a(r, c) = s.a(r, c) * sign[c];
    out.b(r) = s.b(r);
  }
  return out;
}

void require_plain(const Ifs& ifs, const char* role) {
  if (ifs.recurrent() || !ifs.super_ifs().empty() || !ifs.condensation().empty())
    throw InputError(std::string("cannot morph ") + role + " system '" + ifs.name() +
                     "': recurrent transitions, super IFS members and condensation sets are not interpolated");
}

}  // namespace

Ifs pad_maps(const Ifs& ifs, std::size_t maps) {
  ifs.require_affine("padding with maps");
  if (maps < ifs.size() || ifs.size() == 0)
    throw InputError("cannot pad system '" + ifs.name() + "' of " + std::to_string(ifs.size()) + " maps to " +
                     std::to_string(maps));
  std::vector<AffineMap> all = ifs.maps();
  std::vector<double> p = ifs.probabilities();
  const std::size_t copies = maps - ifs.size() + 1;
  const double shared = p.back() / static_cast<double>(copies);
  p.back() = shared;
  for (std::size_t k = 1; k < copies; ++k) {
    all.push_back(ifs.maps().back());
    p.push_back(shared);
  }
  Ifs out(ifs.name(), ifs.layout(), std::move(all), std::move(p));
  out.set_description(ifs.description());
  out.set_render_defaults(ifs.render_defaults());
  return out;
}

Ifs morph(const Ifs& from, const Ifs& to, double t) {
  from.require_affine("morphing");
  to.require_affine("morphing");
  if (!std::isfinite(t) || t < 0.0 || t > 1.0)
    throw InputError("the morph parameter t must lie in [0, 1], got " + std::to_string(t));
  if (!(from.layout() == to.layout()))
    throw InputError("cannot morph '" + from.name() + "' (" + from.layout().text() + ") into '" + to.name() + "' (" +
                     to.layout().text() + "): the layouts differ");
  require_plain(from, "the first");
  require_plain(to, "the second");
  const std::size_t size = std::max(from.size(), to.size());
  const Ifs a = pad_maps(from, size), b = pad_maps(to, size);

  std::vector<AffineMap> maps;
  std::vector<double> p;
  for (std::size_t i = 0; i < size; ++i) {
    maps.push_back(morph_map(a.map(i), b.map(i), a.spatial_dims(), t));
    p.push_back(lerp(a.probabilities()[i], b.probabilities()[i], t));
  }
  std::ostringstream name;
  name << from.name() << " to " << to.name() << " (t = " << t << ")";
  Ifs out(name.str(), from.layout(), std::move(maps), std::move(p));

  const RenderDefaults &da = from.render_defaults(), &db = to.render_defaults();
  RenderDefaults d = t < 0.5 ? da : db;
  if (da.window.size() == 4 && db.window.size() == 4)
    for (int k = 0; k < 4; ++k) d.window[k] = lerp(da.window[k], db.window[k], t);
  if (da.view.size() == 2 && db.view.size() == 2)
    for (int k = 0; k < 2; ++k) d.view[k] = lerp_angle(da.view[k], db.view[k], t);
  out.set_render_defaults(d);
  return out;
}

}  // namespace ifsforge
