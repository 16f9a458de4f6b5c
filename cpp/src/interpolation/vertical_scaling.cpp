#include "ifsforge/interpolation/vertical_scaling.h"

#include <cmath>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/core/random.h"

namespace ifsforge {

std::vector<double> vertical_scaling(std::size_t maps, double roughness, SignPattern signs, std::uint64_t seed,
                                     std::uint64_t stream) {
  check_vertical_scaling({roughness}, "the roughness");
  const double magnitude = std::fabs(roughness);
  std::vector<double> out(maps, magnitude);
  Rng rng(seed, stream);
  for (std::size_t i = 0; i < maps; ++i) {
    if (signs == SignPattern::Alternating && i % 2 == 1) out[i] = -magnitude;
    if (signs == SignPattern::Random && (rng.next() >> 63)) out[i] = -magnitude;
  }
  return out;
}

void check_vertical_scaling(const std::vector<double>& a22, const std::string& what) {
  for (std::size_t i = 0; i < a22.size(); ++i) {
    if (!std::isfinite(a22[i]) || std::fabs(a22[i]) >= 1.0) {
      std::ostringstream s;
      s << what << (a22.size() > 1 ? " [" + std::to_string(i) + "]" : std::string()) << " is " << a22[i]
        << ": a vertical scaling factor needs |a22| < 1, or the maps have no attractor "
           "(the interpolant would not be a continuous function)";
      throw InputError(s.str());
    }
  }
}

}  // namespace ifsforge
