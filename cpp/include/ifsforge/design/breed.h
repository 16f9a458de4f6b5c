#pragma once
/// @file Random polar systems (seed 3.3.3, Eq. 32), drawn as the seed's phenotypes (section 7)
/// are: each a locally contractive system whose attractor is worth a look.
#include <cstdint>
#include <vector>

#include "ifsforge/model/ifs.h"

namespace ifsforge {

struct BreedOptions {
  int count = 16;                 ///< phenotypes to draw
  std::uint64_t seed = 0;         ///< the same seed draws the same phenotypes
  int maps = 0;                   ///< maps per phenotype (2..16); 0: 2 to 4, drawn
  int probe = 64;                 ///< side of the chaos render that judges a draw
  double min_coverage = 0.1;      ///< share of the probe's pixels the attractor must cover
  double max_coverage = 0.6;      ///< ... and may cover at most (a blob is no picture)
  double min_extent = 0.2;        ///< the attractor's box side relative to the centres' spread
  int attempts = 500;             ///< draws per phenotype before giving up
};

/// @brief `count` polar systems, phenotype k drawn from the stream (seed, k) and redrawn from
/// it until it is not degenerate: its attractor spans at least min_extent of the region its
/// centres span (not collapsed to a point) and covers min_coverage..max_coverage of a probe x
/// probe chaos render framed on it. Every map has s_i <= 0.9 (Eq. 30). InputError when a
/// phenotype finds no acceptable draw within `attempts`.
std::vector<Ifs> breed(const BreedOptions& options);

}  // namespace ifsforge
