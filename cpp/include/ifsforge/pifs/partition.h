#pragma once
/// @file Quadtree partition (the seed's Step 1 and Fig. 3.7): which candidate range cells
/// become leaves, by an RMS threshold or by a rate-distortion trade-off.
#include <vector>

#include "ifsforge/pifs/domain_search.h"

namespace ifsforge {

/// @brief Every level's candidates of one plane, index log_size − min_log.
struct PifsPlaneCandidates {
  int width = 0, height = 0;  ///< the plane's own (unpadded) size
  int padded_width = 0, padded_height = 0;
  std::vector<std::vector<PifsCandidate>> levels;
};

/// @brief Leaves split until the collage RMS error (8-bit levels) is at most `rms` or the
/// smallest size is reached; a flat cell is kept when it meets the threshold.
std::vector<PifsLeaf> partition_threshold(const PifsCode& code, const PifsPlaneCandidates& c, double rms);

/// @brief Leaves minimising error × weight + lambda × estimated bits, bottom-up.
std::vector<PifsLeaf> partition_lagrangian(const PifsCode& code, const PifsPlaneCandidates& c, double lambda,
                                           double weight);

}  // namespace ifsforge
