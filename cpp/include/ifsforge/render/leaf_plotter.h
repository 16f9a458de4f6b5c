#pragma once
/// @file Plotting the leaves of the recursive algorithms (string rewriting 5.6, TSA 5.7, AFRA
/// 5.10, the probabilistic domain algorithm 5.12.2): each job collects its leaves, and batches
/// are applied in job order, so floating-point sums do not depend on the thread count.
#include <cstdint>
#include <map>
#include <mutex>
#include <vector>

#include "ifsforge/model/ifs.h"
#include "ifsforge/render/frame.h"
#include "ifsforge/render/raster.h"

namespace ifsforge {

class LeafPlotter {
 public:
  /// @brief The leaves of one job.
  struct Batch {
    std::vector<std::uint32_t> pixel;
    std::vector<double> mass;     ///< measure carried by the leaf
    std::vector<double> weight;   ///< weight of its channel values (mass, kept above 0)
    std::vector<double> moments;  ///< weight x channel value, channels per leaf
    std::vector<float> depth;     ///< 3D systems: depth towards the viewer
  };

  LeafPlotter(const Ifs& ifs, const Frame& frame);
  const Frame& frame() const { return frame_; }

  /// @brief A point of the attractor with its mass (dropped when it falls off the image).
  void plot(Batch& batch, const Point& p, double mass) const;
  /// @brief The images M(p) of `points` sharing `mass` equally, for a piece smaller than a pixel
  /// that may straddle pixels: one entry per distinct pixel (at most four), not per point.
  /// `m` is flat (composed::) or a model map.
  void plot_spread(Batch& batch, const double* m, const std::vector<Point>& points, double mass) const;
  void plot_spread(Batch& batch, const AffineMap& m, const std::vector<Point>& points, double mass) const;
  /// @brief Mass and mass-weighted channel moments straight into a pixel (AFRA).
  void add(Batch& batch, std::uint32_t pixel, double mass, const double* moments) const;
  /// @brief Applies job `job`'s batch after those of every earlier job (thread-safe). Every
  /// job index from 0 up must be submitted exactly once.
  void submit(std::uint64_t job, Batch&& batch);
  /// @brief The raster: density = mass (a covered pixel stays above 0), channels = moments /
  /// weight, depth for 3D; points = leaves plotted.
  Raster finish();

 private:
  template <typename Apply>
  void spread(Batch& batch, Apply&& apply, const std::vector<Point>& points, double mass) const;
  void apply(const Batch& batch);
  Frame frame_;
  int spatial_, channels_;
  Raster raster_;
  std::vector<double> mass_, weight_, moments_;
  std::mutex mutex_;
  std::map<std::uint64_t, Batch> waiting_;
  std::uint64_t next_job_ = 0;
};

/// @brief Affine maps stored flat (n rows of n coefficients, then the n offsets), for address
/// trees that keep one composed map per node.
namespace composed {
constexpr int size(int n) { return n * (n + 1); }
void identity(int n, double* m);
/// @brief out = outer o inner (outer a model map, inner flat).
void after(const AffineMap& outer, const double* inner, int n, double* out);
/// @brief out = outer o inner (outer flat, inner a model map).
void before(const double* outer, const AffineMap& inner, int n, double* out);
Point apply(const double* m, int n, const Point& p);
}  // namespace composed

/// @brief Why a node of an address tree (a piece M(A) of the attractor inside the box M(B))
/// stops: it misses the image, lies inside one pixel, is smaller than a pixel but may straddle
/// pixels, or none of these (keep splitting).
enum class PieceFit { Split, Off, OnePixel, Small };

/// @brief The attractor's box B (attractor_bounds plus a 2% margin) and the pixel boxes of
/// its images M(B) in a frame.
class PieceBoxes {
 public:
  PieceBoxes(const Ifs& ifs, const Frame& frame);
  /// @brief M(B) in continuous pixel coordinates: [lo, hi) per axis (m flat).
  void pixel_box(const double* m, double* lo, double* hi) const;
  PieceFit fit(const double* m) const;
  /// @brief B's centre: a leaf plots at its image, the centre of its piece's box.
  Point center() const;

 private:
  Frame frame_;
  int n_, spatial_;
  std::vector<double> center_, half_;
};

/// @brief Points of the attractor spread over it: the maps' fixed points (those that are
/// finite), their images under the maps (a level or two) and the extremes in every spatial
/// direction of a seeded sample. A leaf smaller than
/// a pixel that may straddle pixels plots the images of these, so no pixel it touches is missed.
std::vector<Point> spread_points(const Ifs& ifs);

}  // namespace ifsforge
