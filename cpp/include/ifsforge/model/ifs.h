#pragma once
/// @file The nD iterated function system with probabilities (seed Definition 10, Eq. 22).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ifsforge/core/names.h"
#include "ifsforge/model/affine_map.h"
#include "ifsforge/model/channel_layout.h"
#include "ifsforge/model/condensation.h"
#include "ifsforge/model/polar_map.h"
#include "ifsforge/model/recurrent.h"
#include "ifsforge/model/super_ifs.h"

namespace ifsforge {

/// @brief Hyperbolic: every map contracts. AverageContractive: Eq. 14 holds. Eventually
/// contractive: neither, but the random matrix products contract (negative top Lyapunov
/// exponent), so random iteration still converges. LocallyContractive: a system with polar maps,
/// each contracting about its centre only (Eq. 30); its orbits stay in a bounded disc.
/// Divergent: none of these.
enum class Classification { Hyperbolic, AverageContractive, EventuallyContractive, LocallyContractive, Divergent };
template <>
struct EnumNames<Classification> {
  static constexpr const char* what = "classification";
  static constexpr NamedValue<Classification> values[] = {
      {Classification::Hyperbolic, "hyperbolic"},
      {Classification::AverageContractive, "average-contractive"},
      {Classification::EventuallyContractive, "eventually-contractive"},
      {Classification::LocallyContractive, "locally-contractive"},
      {Classification::Divergent, "divergent"}};
};

/// @brief Optional rendering hints stored with a system (the JSON "render" object).
struct RenderDefaults {
  std::vector<double> window;  ///< empty, or xmin ymin xmax ymax
  std::vector<double> view;    ///< empty, or yaw pitch (degrees, 3D systems)
  std::string algorithm;       ///< empty: the caller's default
  int width = 0, height = 0;   ///< 0: the caller's default
};

/// @brief A closed interval per channel.
struct Bounds {
  std::vector<double> lo, hi;
};

class Ifs {
 public:
  Ifs() = default;
  /// @brief Validates: 1..kMaxDim dimensions matching the layout, finite coefficients,
  /// probabilities finite, >= 0 and summing to a positive number (they are normalised).
  /// Empty `probabilities` means Jacobian-proportional (Eq. 46).
  Ifs(std::string name, ChannelLayout layout, std::vector<AffineMap> maps,
      std::vector<double> probabilities = {});

  const std::string& name() const { return name_; }
  void set_name(std::string name) { name_ = std::move(name); }
  const std::string& description() const { return description_; }
  void set_description(std::string d) { description_ = std::move(d); }
  const RenderDefaults& render_defaults() const { return render_defaults_; }
  void set_render_defaults(RenderDefaults d) { render_defaults_ = std::move(d); }
  const ChannelLayout& layout() const { return layout_; }
  int dim() const { return layout_.dim(); }
  int spatial_dims() const { return layout_.spatial_dims(); }
  std::size_t size() const { return maps_.size(); }
  const std::vector<AffineMap>& maps() const { return maps_; }
  const AffineMap& map(std::size_t i) const { return maps_[i]; }
  const std::vector<double>& probabilities() const { return probabilities_; }
  /// @brief Map i applied to p: its polar map where it has one, else its affine map.
  Point apply(std::size_t i, const Point& p) const {
    if (polar_.empty() || !polar_[i]) return maps_[i](p);
    Point q = maps_[i](p);
    polar_[i]->apply(p.data(), q.data());
    return q;
  }

  /// @brief Spectral norm of each map's whole linear part (Eq. 8-9 in 2D); for a polar map,
  /// its shadow's, whose spatial block is s_i I (Eq. 30).
  std::vector<double> contraction_factors() const;
  /// @brief Spectral norm of each map's spatial block.
  std::vector<double> spatial_contraction_factors() const;
  /// @brief Eq. 10 as the seed intends it (its printed form is garbled): max_i s_i.
  double contraction_ratio() const;
  /// @brief Eq. 14 in log form: sum_i p_i log s_i (negative means contractive on average).
  double average_log_contraction() const;
  /// @brief Estimated top Lyapunov exponent of the random products of the linear parts.
  double lyapunov_exponent(std::size_t steps = 20000, std::uint64_t seed = 1) const;
  Classification classify() const;
  /// @brief Throws DivergentSystemError unless the system has an attractor.
  void require_attractor() const;
  /// @brief Fixed point of map i (if any).
  std::vector<Point> fixed_points() const;
  /// @brief A point on (or, for non-hyperbolic systems, near) the attractor.
  Point start_point() const;
  /// @brief Bounds of the attractor per channel, from a seeded sample of `samples` points.
  /// Hyperbolic or locally contractive (polar): min/max. Otherwise the 0.1% / 99.9%
  /// quantiles (the measure's bulk; the support may be unbounded).
  /// The walk on up to `threads` cores (0: all) where it allows (sample_extent): the same bounds.
  Bounds attractor_bounds(std::size_t samples = 1u << 20, int threads = 1) const;

  /// @name Extensions of the model (the setters validate; they are defined in recurrent.cpp,
  /// super_ifs.cpp, condensation.cpp and polar_map.cpp). At most one of them is set on a system.
  /// @brief Recurrent IFS (3.3.1): empty, or N x N transitions. Setting them replaces the
  /// probabilities by the chain's stationary distribution (the long-run map frequencies).
  const TransitionMatrix& transitions() const { return transitions_; }
  void set_transitions(TransitionMatrix transitions);
  bool recurrent() const { return !transitions_.empty(); }
  /// @brief Super IFS (3.3.5): how the maps split into member systems; empty for one system.
  const SuperIfs& super_ifs() const { return super_; }
  void set_super_ifs(SuperIfs super_ifs);
  /// @brief Condensation set (3.1): empty, or the set C of w_0 (2D systems).
  const Condensation& condensation() const { return condensation_; }
  void set_condensation(Condensation condensation);
  /// @brief Polar maps (3.3.3, Eq. 30-32; defined in polar_map.cpp): empty, or one entry per
  /// map of a 2D system, nullopt for an affine map. Setting them makes each polar map's
  /// AffineMap its shadow (PolarMap::shadow), which keeps its channel rows; the renderers that
  /// know polar maps (chaos, prr) apply the polar map itself, the others refuse the system.
  const std::vector<std::optional<PolarMap>>& polar_maps() const { return polar_; }
  void set_polar_maps(std::vector<std::optional<PolarMap>> polar);
  bool polar() const { return !polar_.empty(); }
  /// @brief InputError naming `what` when the system has polar maps: for code that composes,
  /// inverts or interpolates the affine maps (it would silently use the shadows).
  void require_affine(const std::string& what) const;

 private:
  std::string name_ = "untitled";
  std::string description_;
  RenderDefaults render_defaults_;
  ChannelLayout layout_;
  std::vector<AffineMap> maps_;
  std::vector<double> probabilities_;
  TransitionMatrix transitions_;
  SuperIfs super_;
  Condensation condensation_;
  std::vector<std::optional<PolarMap>> polar_;
};

/// @brief Calls `visit` with `count` points of a seeded random iteration (5.1.1, the walk of
/// model/orbit.h: a recurrent system's transitions followed) that starts on the attractor and
/// skips 100 points; throws DivergentSystemError if the orbit escapes.
void sample_attractor(const Ifs& ifs, std::size_t count, std::uint64_t seed,
                      const std::function<void(const Point&)>& visit);

/// Writes the k values (at most 8) that stand for a point.
using ExtentView = std::function<void(const Point&, double* values)>;

/// @brief The least and greatest of each of the `k` values `view` gives sample_attractor's
/// points, the first of equal ones kept as a scan in order keeps it: the same numbers whatever
/// `threads` (0: all cores). A 2D or 3D affine system's walk is cut into pieces walked side by
/// side, each checked to continue the one before bit for bit (model/attractor_extent.cpp).
void sample_extent(const Ifs& ifs, std::size_t count, std::uint64_t seed, int k, const ExtentView& view, double* lo,
                   double* hi, int threads = 1);

/// @brief The q-quantile of `values` (reorders them).
double quantile(std::vector<double>& values, double q);

/// @brief Eq. 46: probabilities proportional to |det| of the spatial block, with a floor
/// of 1% of the largest so that degenerate maps (det 0, like the fern's stem) still appear.
std::vector<double> jacobian_probabilities(const std::vector<AffineMap>& maps, int spatial_dims);

}  // namespace ifsforge
