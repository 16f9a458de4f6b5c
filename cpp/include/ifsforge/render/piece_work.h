#pragma once
/// @file How much work an address tree is before it is walked: the algorithms that split
/// every piece until it fits a pixel (string rewriting 5.6, AFRA 5.10, the probabilistic
/// domain 5.12.2) estimate it first and refuse work that has no bound or exceeds the budget.
#include <string>

#include "ifsforge/model/ifs.h"
#include "ifsforge/render/frame.h"

namespace ifsforge {

/// @brief About how many pieces an address tree visits when every piece is split until its
/// box, the attractor's box shrunk by the product of the maps' spatial contraction factors
/// s_i, is at most 1/`ratio` of it: N(x) = 1 + sum_i N(x - log 1/s_i), x = log(ratio) still
/// to go. Pieces overlap when sum |det| > 1, and then N grows as ratio^D with D above the
/// dimension of the space (faster than the pixels). An upper bound where a map shrinks
/// boxes faster than its norm or pieces leave the image; infinite when a map does not
/// contract.
double estimated_pieces(const Ifs& ifs, double ratio);

/// @brief InputError naming `algorithm` and the estimate when splitting pieces down to
/// `leaf` pixels across (1: a pixel; AFRA: a quarter) on `frame` would visit more than
/// kPiecesPerPixel pieces per pixel (at least kMinPieceWork in all), or hold more than the
/// memory budget at `bytes_per_piece` for each piece of the widest level.
void check_piece_work(const Ifs& ifs, const Frame& frame, double leaf, double bytes_per_piece,
                      const std::string& algorithm);

constexpr double kPiecesPerPixel = 256;
constexpr double kMinPieceWork = 1u << 26;

}  // namespace ifsforge
