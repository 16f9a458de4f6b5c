#pragma once
/// @file Reading the algorithm-specific settings of RenderOptions::parameters, with errors
/// that name the algorithm, the setting and what it accepts.
#include <map>
#include <string>
#include <vector>

#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// Limits on options that only burn time or memory (a render asking for more is refused).
constexpr std::uint64_t kMaxIterations = 1'000'000'000'000ull;  ///< 10^12 points
constexpr double kMaxPointsPerPixel = 1e6;
constexpr int kMaxDepth = 64;  ///< recursive renderers stop at 64 levels anyway
constexpr int kMaxThreads = 1024;

/// @brief InputError naming the option when a size, count or depth is out of range;
/// MemoryBudgetError when the raster alone would not fit the memory budget.
void check_render_options(const RenderOptions& options);

/// @brief check_render_options, then InputError unless every name in options.parameters is one
/// `renderer` declares.
void check_parameters(const Renderer& renderer, const RenderOptions& options);

/// @brief The settings of one render: the caller's values over the renderer's defaults.
class ParameterValues {
 public:
  /// @brief Checks the names (check_parameters) and merges them with the defaults.
  ParameterValues(const Renderer& renderer, const RenderOptions& options);

  /// @brief The text of `name` ("" when it is left to the algorithm).
  const std::string& text(const std::string& name) const;
  bool automatic(const std::string& name) const { return text(name).empty(); }
  /// @brief A number in [lo, hi]; InputError otherwise.
  double number(const std::string& name, double lo, double hi) const;
  /// @brief A whole number in [lo, hi]; InputError otherwise.
  long long integer(const std::string& name, long long lo, long long hi) const;
  /// @brief One of `allowed`; InputError listing them otherwise.
  std::string choice(const std::string& name, const std::vector<std::string>& allowed) const;

 private:
  [[noreturn]] void fail(const std::string& name, const std::string& expected) const;
  std::string algorithm_;
  std::map<std::string, std::string> values_;
};

}  // namespace ifsforge
