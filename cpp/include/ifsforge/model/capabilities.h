#pragma once
/// @file What a system asks of the algorithm that draws it, and what each algorithm declares it
/// handles. Every renderer, volume renderer and sampler declares its Capabilities; the check is
/// made once where it is called (Renderer::render, VolumeRenderer::render, the samplers) and a
/// refusal names the algorithms of the same kind that do handle the system.
#include <string>
#include <utility>
#include <vector>

#include "ifsforge/model/ifs.h"

namespace ifsforge {

/// @brief The features of a system beyond an ordinary hyperbolic IFS with disjoint-enough pieces.
struct SystemFeatures {
  bool recurrent = false;            ///< transitions (3.3.1)
  bool polar = false;                ///< polar maps (3.3.3)
  bool average_contractive = false;  ///< average- or eventually-contractive (Eq. 14), a map expanding in space
  bool overlapping = false;          ///< the pieces overlap: sum of |det| of the spatial blocks above 1
  bool condensation = false;         ///< a condensation set (3.1)
  int spatial_dims = 2;
  Classification classification = Classification::Hyperbolic;
  double determinant_sum = 0.0;  ///< sum over the maps of |det| of the spatial block
  int expanding_map = -1;        ///< a map whose spatial_shrink is >= 1 (0-based), or -1
  double expanding_factor = 0.0;
};

/// @brief The features of `ifs`.
SystemFeatures system_features(const Ifs& ifs);

/// @brief How much map `m` shrinks a piece of space per application in the long run: the
/// spectral radius of its spatial block (`spatial_dims` <= 3), ~ ||A^32||^(1/32). Its norm
/// overstates it for a map that turns or shears (volume_coral_6d's fourth map: norm 1.25,
/// radius 0.66).
double spatial_shrink(const AffineMap& m, int spatial_dims);

/// @brief What an algorithm handles, as flags; 2D and 3D are the spatial dimensions it takes.
struct Capabilities {
  enum Flag : unsigned {
    Recurrent = 1u << 0,           ///< follows a recurrent system's transitions
    Polar = 1u << 1,               ///< applies polar maps themselves (not their affine shadows)
    AverageContractive = 1u << 2,  ///< systems with an expanding map
    Overlapping = 1u << 3,         ///< systems whose pieces overlap, within bounded work
    Condensation = 1u << 4,        ///< draws a condensation set
    Plane = 1u << 5,               ///< 2 spatial dimensions
    Space = 1u << 6,               ///< 3 spatial dimensions
  };
  unsigned flags = 0;
  bool has(Flag f) const { return (flags & f) != 0; }
};

/// @brief Flag names and what they mean, in Flag order (for listings: `ifsforge algorithms`).
struct CapabilityName {
  Capabilities::Flag flag;
  const char* name;
  const char* meaning;
};
const std::vector<CapabilityName>& capability_names();
/// @brief Each flag by its name (capability_names), for listings and bindings.
std::vector<std::pair<std::string, bool>> capability_flags(const Capabilities& c);

/// @brief Why an algorithm with `c` does not handle a system with `f` named `system`, as a
/// clause ("does not follow transitions, and system 'x' is a recurrent IFS (3.3.1)"), or empty
/// when it does.
std::string unhandled_reason(const Capabilities& c, const SystemFeatures& f, const std::string& system);

/// @brief InputError unless `c` handles `ifs`: "<kind> '<name>' <reason>; use <others>", the
/// others being the entries of `all` that handle it (or a note that none does).
void require_handles(const std::string& kind, const std::string& name, const Capabilities& c, const Ifs& ifs,
                     const std::vector<std::pair<std::string, Capabilities>>& all);
/// @brief The same for features already computed.
void require_handles(const std::string& kind, const std::string& name, const Capabilities& c, const Ifs& ifs,
                     const SystemFeatures& f, const std::vector<std::pair<std::string, Capabilities>>& all);

/// @brief (name, capabilities) of every entry of a renderer registry (entries hold `renderer`),
/// in registration order: the table refusals name the alternatives from.
template <typename Registry>
std::vector<std::pair<std::string, Capabilities>> capability_table(const Registry& registry) {
  std::vector<std::pair<std::string, Capabilities>> out;
  for (const auto& entry : registry) out.emplace_back(entry.renderer->name(), entry.renderer->capabilities());
  return out;
}

/// @brief The samplers of random iteration (5.1.1) and what they handle: sample_points
/// (sample_attractor) and preview_cloud.
const std::vector<std::pair<std::string, Capabilities>>& sampler_capabilities();
/// @brief require_handles for the sampler called `name`.
void require_sampler_handles(const std::string& name, const Ifs& ifs);

}  // namespace ifsforge
