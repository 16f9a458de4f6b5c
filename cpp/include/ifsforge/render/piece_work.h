#pragma once
/// @file How much work an address tree may be: the algorithms that split every piece until it
/// fits a pixel (string rewriting 5.6, AFRA 5.10, the probabilistic domain 5.12.2) estimate
/// it before they start and count it while they run, and stop with an InputError that names
/// the reason and the algorithms to use instead, rather than run for minutes.
#include <atomic>
#include <cstdint>
#include <string>

#include "ifsforge/model/ifs.h"
#include "ifsforge/render/frame.h"

namespace ifsforge {

/// @brief About how many pieces an address tree visits when every piece is split until its
/// box, the attractor's box shrunk by the product of the maps' shrink factors s_i (spectral
/// radii of the spatial blocks), is at most 1/`ratio` of it, or `max_depth` levels deep:
/// N(x) = 1 + sum_i N(x - log 1/s_i), x = log(ratio) still to go. Pieces overlap when sum
/// |det| > 1, and then N grows as ratio^D with D above the dimension of the space (faster
/// than the pixels). It errs high (2-4x on the samples: pieces leave the image, boxes are
/// not tight); infinite when a map does not shrink.
double estimated_pieces(const Ifs& ifs, double ratio, int max_depth = 64);

/// Pieces an algorithm may visit per pixel of the image (at least kMinPieceWork in all).
constexpr double kPiecesPerPixel = 64;
constexpr double kMinPieceWork = 1u << 24;
/// The estimate errs high: it refuses only beyond this multiple of the work allowed, and the
/// count while running does the rest.
constexpr double kEstimateSlack = 4;

/// @brief The work allowed to one render of `algorithm` on `frame`, splitting pieces down to
/// `leaf` pixels across (1: a pixel; AFRA: a quarter). The constructor refuses a render whose
/// estimate is far beyond it; spend() counts the pieces the jobs visit and refuses once they
/// pass it.
class PieceBudget {
 public:
  PieceBudget(const Ifs& ifs, const Frame& frame, double leaf, std::string algorithm);
  /// @brief Adds `pieces` visited by a job (call it every few thousand); InputError once the
  /// render's total passes the limit.
  void spend(std::uint64_t pieces);
  double limit() const { return limit_; }

 private:
  [[noreturn]] void refuse(double pieces, const char* how) const;
  const Ifs& ifs_;
  int width_, height_;
  std::string algorithm_;
  double limit_;
  std::atomic<std::uint64_t> spent_{0};
};

}  // namespace ifsforge
