#pragma once
// The structural start of the planar fit: the target covered by copies of itself chosen one at
// a time over the full circle of turns (each part of the target is a copy of the whole, Eq. 41).
#include <cstdint>
#include <functional>
#include <vector>

#include "fit_raster.h"
#include "ifsforge/core/random.h"

namespace ifsforge {

/// @brief decode_map parameters (6 per map: signed scales, turns, translation) of `maps`
/// similarities covering the target: from each of a beam of first copies (the best of each lattice
/// scale, so that a cover may start below the copy covering most, as a terdragon's third does
/// where its whole turned half a turn covers more), the copies are added greedily, each the one
/// that covers most of the target not yet covered, against the cells it puts off the target and
/// on earlier copies; the cover worth most wins. A copy is chosen among kCoverScales x kCoverTurns
/// (from a seeded offset) x 2 mirrors with its centroid on a seeded lattice of target cells not
/// yet covered, the moment maps of the target's pieces and of what the cover leaves
/// (fit_moments.h), and the earlier copies carried by the target's likely symmetries; the best
/// few of each climb, judged by where the picture `full`'s own pixels land on a grid of
/// `judge_raster` cells along the long side (the search's: lenient to a thin target's large
/// copies; the picture's: strict with copies of nearly the whole); without `beam`, only the greedy
/// cover from the copy worth most (a few of its copies' work). The same for any thread count;
/// candidates tried are added to `evaluations`; once `stop` turns true no further cover is begun.
std::vector<double> self_similar_cover(const PixelSet& full, const PixelSet& target, const FitGrid& grid, int maps,
                                       int judge_raster, double max_contraction, bool beam, int threads, Rng& rng,
                                       std::uint64_t& evaluations, const std::function<bool()>& stop);

}  // namespace ifsforge
