#include "ifsforge/model/polar_map.h"

#include <cmath>
#include <cstdlib>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/model/ifs.h"

namespace ifsforge {

double PolarMap::f_bound() const {
  return f[0] + std::abs(f[1]) + std::hypot(f[2], f[3]) + std::hypot(f[4], f[5]);
}

// (tanh(x) + 1) / 2 = 1 / (1 + e^(-2x)): one exp, and the same formula for s_i and for each
// image keeps |P w(M)| <= s_i |P M| exact in floating point (both are monotone in F).
double PolarMap::contraction() const { return 1.0 / (1.0 + std::exp(-2.0 * k * f_bound())); }

void PolarMap::apply(const double* in, double* out) const {
  const double dx = in[0] - center[0], dy = in[1] - center[1];
  const double rho = std::sqrt(dx * dx + dy * dy);
  if (rho == 0.0) {  // P is fixed: rho' = 0 whatever theta
    out[0] = center[0];
    out[1] = center[1];
    return;
  }
  // cos and sin of theta from PM (Eq. 31), and of 2 theta and w theta by complex powers:
  // no atan2, one exp and one sincos per point.
  const double c = dx / rho, s = dy / rho;
  const double F = f[0] + (f[1] != 0.0 ? f[1] * std::tanh(rho) : 0.0) + f[2] * c + f[3] * s +
                   f[4] * (c * c - s * s) + f[5] * (2.0 * c * s);
  const double r = rho / (1.0 + std::exp(-2.0 * k * F));  // Eq. 32
  double wc = 1.0, ws = 0.0;
  for (int i = 0; i < std::abs(winding); ++i) {
    const double t = wc * c - ws * s;
    ws = wc * s + ws * c;
    wc = t;
  }
  if (winding < 0) ws = -ws;
  const double phi = g[0] + g[1] * rho + g[2] * c + g[3] * s;
  const double pc = std::cos(phi), ps = std::sin(phi);
  out[0] = center[0] + r * (wc * pc - ws * ps);
  out[1] = center[1] + r * (wc * ps + ws * pc);
}

void PolarMap::validate(const std::string& what) const {
  auto check = [&](double v, const std::string& field) {
    if (!std::isfinite(v)) throw InputError(what + ": " + field + " is not a finite number");
    if (std::abs(v) > kMaxCoefficient)
      throw InputError(what + ": " + field + " is larger than " + std::to_string(kMaxCoefficient) + " in magnitude");
  };
  check(center[0], "center x");
  check(center[1], "center y");
  check(k, "k");
  if (!(k > 0.0)) throw InputError(what + ": k must be greater than 0");
  for (int i = 0; i < kF; ++i) check(f[i], "F[" + std::to_string(i) + "]");
  for (int i = 0; i < kG; ++i) check(g[i], "G[" + std::to_string(i) + "]");
  if (winding < -kMaxWinding || winding > kMaxWinding)
    throw InputError(what + ": the winding must be a whole number in -" + std::to_string(kMaxWinding) + ".." +
                     std::to_string(kMaxWinding));
  if (!(contraction() < 1.0))
    throw InputError(what + ": k sup F = " + std::to_string(k * f_bound()) +
                     " is so large that s = (tanh(k sup F) + 1) / 2 rounds to 1 (Eq. 30 needs s < 1)");
}

AffineMap PolarMap::shadow(const AffineMap& channels) const {
  AffineMap m = channels;
  const double s = contraction();
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < m.dim(); ++c) m.a(r, c) = r == c ? s : 0.0;
    m.b(r) = (1.0 - s) * center[r];
  }
  return m;
}

void Ifs::set_polar_maps(std::vector<std::optional<PolarMap>> polar) {
  bool any = false;
  for (const auto& p : polar) any |= p.has_value();
  if (!any) {
    polar_.clear();
    return;
  }
  const std::string what = "system '" + name_ + "'";
  if (polar.size() != maps_.size())
    throw InputError(what + " has " + std::to_string(maps_.size()) + " maps but " + std::to_string(polar.size()) +
                     " polar entries");
  if (spatial_dims() != 2) throw InputError(what + ": polar maps are maps of the plane (2D systems only)");
  if (recurrent() || !super_.empty() || !condensation_.empty())
    throw InputError(what + ": a system with polar maps cannot also be recurrent, a super IFS or have a condensation set");
  for (std::size_t i = 0; i < polar.size(); ++i)
    if (polar[i]) {
      polar[i]->validate("polar map " + std::to_string(i + 1));
      maps_[i] = polar[i]->shadow(maps_[i]);
    }
  polar_ = std::move(polar);
}

void Ifs::require_affine(const std::string& what) const {
  if (polar())
    throw InputError(what + " needs affine maps, and system '" + name_ +
                     "' has polar maps (3.3.3); render it with chaos or prr");
}

Ifs polar_ifs(std::string name, const std::vector<PolarMap>& maps, std::vector<double> probabilities) {
  if (maps.empty()) throw InputError("a system needs at least one map");
  std::vector<AffineMap> shadows;
  std::vector<std::optional<PolarMap>> polar;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    maps[i].validate("polar map " + std::to_string(i + 1));
    shadows.push_back(maps[i].shadow(AffineMap(2)));
    polar.emplace_back(maps[i]);
  }
  Ifs ifs(std::move(name), ChannelLayout("xy"), std::move(shadows), std::move(probabilities));
  ifs.set_polar_maps(std::move(polar));
  return ifs;
}

}  // namespace ifsforge
