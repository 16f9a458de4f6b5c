#pragma once
/// @file The common interface of the 2D rendering algorithms (seed chapter 5) and their
/// registry, so that Python and the CLI choose one by name.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ifsforge/core/progress.h"
#include "ifsforge/model/capabilities.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/render/frame.h"
#include "ifsforge/core/image.h"
#include "ifsforge/render/raster.h"

namespace ifsforge {

/// Runs jobs [first, last) of a render elsewhere (on a cluster) and returns their results as
/// Renderer::run_jobs bytes of consecutive ranges, in job order (each renderer merges them
/// exactly: integer sums, or leaves applied in address order). As for volumes, the runner
/// keeps the bytes alive until its next call or its end: the merge reads them in place.
/// `depth`: the options' depth, except that a point-recursive render whose pieces ran past
/// their node budget falls back to a fixed depth, which the jobs must then run at too.
using RenderJobRunner =
    std::function<std::vector<std::string_view>(std::uint64_t first, std::uint64_t last, int depth)>;

struct RenderOptions {
  int width = 1024, height = 1024;
  std::optional<Window> window;  ///< default: the attractor's bounds
  View view;                     ///< for 3D systems
  /// Random iteration: points to plot; 0 picks Eq. 44 (density) or Eq. 45 (binary).
  std::uint64_t iterations = 0;
  bool binary = false;            ///< only coverage matters (sets the default counts)
  double points_per_pixel = 16;   ///< PEPP of Eq. 44
  std::uint64_t skip = 100;       ///< min_no_of_iterations (5.1.1)
  int depth = 0;                  ///< recursive renderers: 0 picks Eq. 59 and a pixel-size cut
  std::uint64_t seed = 0;
  int threads = 0;                ///< 0: every core; the output never depends on it
  ProgressCallback progress;
  /// Colour stealing (5.1.2): the picture colours are taken from, and the system that walks
  /// it (same number of maps; default: a grid of cells over the unit square).
  std::shared_ptr<const Image> reference_image;
  std::shared_ptr<const Ifs> reference_system;
  /// Algorithm-specific settings by name, as text (Renderer::parameters() lists each
  /// algorithm's names and defaults; an unknown name is an InputError).
  std::map<std::string, std::string> parameters;
  /// Empty: the jobs run here on `threads` threads. Set: chaos and prr hand their jobs to it.
  RenderJobRunner distribute;
};

/// @brief One algorithm-specific setting: its name, default ("" = chosen automatically) and
/// what it does.
struct RendererParameter {
  std::string name, default_value, description;
};

class Renderer {
 public:
  virtual ~Renderer() = default;
  virtual std::string name() const = 0;
  virtual std::string description() const = 0;
  /// @brief The systems it draws: render and run_jobs refuse any other before any work, with an
  /// InputError naming the renderers that do draw it.
  virtual Capabilities capabilities() const = 0;
  /// @brief Renders `ifs` (which must have an attractor) into a raster.
  Raster render(const Ifs& ifs, const RenderOptions& options) const;
  /// @brief The settings this algorithm reads from RenderOptions::parameters.
  virtual std::vector<RendererParameter> parameters() const { return {}; }
  /// @brief Jobs [first, last) of the render `options` describe, as bytes that render() merges
  /// exactly when `options.distribute` returns them: what a cluster's worker runs. InputError
  /// for a renderer whose work does not split into independent jobs.
  std::string run_jobs(const Ifs& ifs, const RenderOptions& options, std::uint64_t first, std::uint64_t last) const;
  /// @brief Whether run_jobs and RenderOptions::distribute work for this renderer.
  virtual bool distributable() const { return false; }
  /// @brief InputError unless capabilities() covers `ifs` (what render and run_jobs check).
  void require_handles(const Ifs& ifs) const;

 protected:
  /// @brief render() and run_jobs() once the system is known to be handled.
  virtual Raster draw(const Ifs& ifs, const RenderOptions& options) const = 0;
  virtual std::string draw_jobs(const Ifs& ifs, const RenderOptions& options, std::uint64_t first,
                                std::uint64_t last) const;
};

/// @brief The renderer called `name` (or one of its aliases); InputError lists the choices.
const Renderer& renderer(const std::string& name);
/// @brief Where the seed describes a renderer, and the operations it estimates for a
/// 1000 x 1000 image of a 5-map IFS (5.13.1, Eq. 75-88; 0 where it gives none).
struct SeedReference {
  std::string section;
  double operations = 0;
};
/// @brief The seed reference of the renderer called `name` (or an alias).
SeedReference seed_reference(const std::string& name);
/// @brief Every renderer, in the order of the seed's chapter 5.
std::vector<const Renderer*> renderers();
/// @brief Every renderer's name and capabilities, in that order.
const std::vector<std::pair<std::string, Capabilities>>& renderer_capabilities();

/// @brief Eq. 44 (density: H V 8 PEPP) or Eq. 45 (binary: H V ln(mu H V), mu = e^gamma).
std::uint64_t default_iterations(int width, int height, bool binary, double points_per_pixel);
/// @brief Eq. 59: the smallest L with N^L >= H V.
int default_depth(std::size_t maps, int width, int height);

}  // namespace ifsforge
