#include "ifsforge/model/capabilities.h"

#include <cmath>
#include <cstdio>

#include "ifsforge/core/error.h"

namespace ifsforge {
namespace {

std::string number(double v, const char* format = "%.3g") {
  char text[32];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

}  // namespace

double spatial_shrink(const AffineMap& m, int k) {
  double a[9], b[9];
  for (int r = 0; r < k; ++r)
    for (int c = 0; c < k; ++c) a[r * k + c] = m.a(r, c);
  double log_scale = 0.0;  // log of the factor taken out of a: A^(2^step) = e^log_scale a
  for (int step = 0; step < 5; ++step) {
    double largest = 0.0;
    for (int r = 0; r < k; ++r)
      for (int c = 0; c < k; ++c) {
        double v = 0.0;
        for (int j = 0; j < k; ++j) v += a[r * k + j] * a[j * k + c];
        b[r * k + c] = v;
        largest = std::max(largest, std::abs(v));
      }
    if (!(largest > 0.0)) return 0.0;  // nilpotent: the piece collapses
    for (int j = 0; j < k * k; ++j) a[j] = b[j] / largest;
    log_scale = 2.0 * log_scale + std::log(largest);
  }
  return std::exp(log_scale / 32.0);
}

SystemFeatures system_features(const Ifs& ifs) {
  SystemFeatures f;
  f.recurrent = ifs.recurrent();
  f.polar = ifs.polar();
  f.condensation = !ifs.condensation().empty();
  f.spatial_dims = ifs.spatial_dims();
  f.classification = ifs.classify();
  for (std::size_t i = 0; i < ifs.size(); ++i) {
    f.determinant_sum += std::abs(ifs.map(i).determinant(f.spatial_dims));
    const double shrink = spatial_shrink(ifs.map(i), f.spatial_dims);
    if (!(shrink < 1.0) && f.expanding_map < 0) {
      f.expanding_map = static_cast<int>(i);
      f.expanding_factor = shrink;
    }
  }
  // A map that expands in space in the long run (not only in its colour channels, nor for one
  // step of a turn: volume_coral_6d's) keeps some pieces from ever shrinking: what the
  // algorithms that split pieces down to the pixel cannot take.
  f.average_contractive = (f.classification == Classification::AverageContractive ||
                           f.classification == Classification::EventuallyContractive) &&
                          f.expanding_map >= 0;
  // Pieces w_i(A) of total measure sum |det| > 1 cannot tile A: they overlap, and an
  // enumeration of addresses down to a pixel visits (pixels)^(D/d) pieces, D > d.
  f.overlapping = f.classification == Classification::Hyperbolic && f.determinant_sum > 1.0 + 1e-6;
  return f;
}

const std::vector<CapabilityName>& capability_names() {
  static const std::vector<CapabilityName> names = {
      {Capabilities::Recurrent, "recurrent", "follows a recurrent system's transitions (3.3.1)"},
      {Capabilities::Polar, "polar", "applies polar maps (3.3.3)"},
      {Capabilities::AverageContractive, "average_contractive",
       "systems with an expanding map (average- or eventually-contractive, Eq. 14)"},
      {Capabilities::Overlapping, "overlapping", "systems whose pieces overlap (sum of |det| above 1)"},
      {Capabilities::Condensation, "condensation", "draws a condensation set (3.1)"},
      {Capabilities::Plane, "2d", "2 spatial dimensions"},
      {Capabilities::Space, "3d", "3 spatial dimensions"}};
  return names;
}

std::vector<std::pair<std::string, bool>> capability_flags(const Capabilities& c) {
  std::vector<std::pair<std::string, bool>> out;
  for (const CapabilityName& n : capability_names()) out.emplace_back(n.name, c.has(n.flag));
  return out;
}

std::string unhandled_reason(const Capabilities& c, const SystemFeatures& f, const std::string& system) {
  const std::string named = "system '" + system + "'";
  if (f.spatial_dims == 2 && !c.has(Capabilities::Plane))
    return "needs a 3D system (layout xyz, xyz+rgb, ...), and " + named + " has 2 spatial dimensions";
  if (f.spatial_dims == 3 && !c.has(Capabilities::Space))
    return "works on the image plane (a 2D system), and " + named + " has 3 spatial dimensions";
  if (f.recurrent && !c.has(Capabilities::Recurrent))
    return "does not follow transitions, and " + named + " is a recurrent IFS (3.3.1)";
  if (f.polar && !c.has(Capabilities::Polar))
    return "does not render polar maps (3.3.3), and " + named + " has them (it would draw their affine shadows)";
  if (f.condensation && !c.has(Capabilities::Condensation))
    return "cannot draw the condensation set of " + named;
  if (f.average_contractive && !c.has(Capabilities::AverageContractive))
    return "needs every map to contract, and " + named + " is " +
           std::string(name_of(f.classification)) + " (map " + std::to_string(f.expanding_map + 1) +
           " expands space by " + number(f.expanding_factor) + " per step" +
           "): its pieces never shrink below a pixel, so the work has no bound";
  if (f.overlapping && !c.has(Capabilities::Overlapping))
    return "enumerates pieces down to the pixel, and the pieces of " + named + " overlap (sum of |det| = " +
           number(f.determinant_sum) + " > 1): the pieces grow faster than the pixels, without a bound on the work";
  return {};
}

void require_handles(const std::string& kind, const std::string& name, const Capabilities& c, const Ifs& ifs,
                     const SystemFeatures& f, const std::vector<std::pair<std::string, Capabilities>>& all) {
  const std::string reason = unhandled_reason(c, f, ifs.name());
  if (reason.empty()) return;
  std::vector<std::string> others;
  for (const auto& [other, caps] : all)
    if (unhandled_reason(caps, f, ifs.name()).empty()) others.push_back(other);
  std::string use;
  for (std::size_t k = 0; k < others.size(); ++k)
    use += (k == 0 ? "" : k + 1 == others.size() ? " or " : ", ") + others[k];
  throw InputError(kind + " '" + name + "' " + reason + "; " + (others.empty() ? "no " + kind + " handles it" : "use " + use));
}

void require_handles(const std::string& kind, const std::string& name, const Capabilities& c, const Ifs& ifs,
                     const std::vector<std::pair<std::string, Capabilities>>& all) {
  require_handles(kind, name, c, ifs, system_features(ifs), all);
}

const std::vector<std::pair<std::string, Capabilities>>& sampler_capabilities() {
  using C = Capabilities;
  static const std::vector<std::pair<std::string, Capabilities>> samplers = {
      // Random iteration follows the walker's chain and applies polar maps (Ifs::apply).
      {"sample_points", {C::Recurrent | C::Polar | C::AverageContractive | C::Overlapping | C::Plane | C::Space}},
      {"preview_cloud", {C::Recurrent | C::AverageContractive | C::Overlapping | C::Plane | C::Space}}};
  return samplers;
}

void require_sampler_handles(const std::string& name, const Ifs& ifs) {
  for (const auto& [sampler, caps] : sampler_capabilities())
    if (sampler == name) return require_handles("sampler", name, caps, ifs, sampler_capabilities());
  throw InputError("no sampler '" + name + "'");
}

}  // namespace ifsforge
