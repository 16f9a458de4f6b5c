#pragma once
/// @file The string-rewriting algorithm (seed 5.6): address strings rewritten level by level.
#include <string>
#include <vector>

#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// String_A starts as the one-map strings w1 ... wN; each rewrite replaces every string by its
/// N successors, breadth first, String_A and String_B taking turns. A string s stands for the
/// piece w_s1 o ... o w_sL (A) of the attractor and is kept as its composed map, so writing a
/// successor costs one map composition. The seed writes the new map in front
/// (new_string = w @ string(k) @ STR_J, see string_rewriting()); here it goes at the end,
/// STR w_k. Strings of one length form the same set either way, but written at the end a
/// string's successors are the sub-pieces of its piece, so a string can be finished early
/// without losing any of the attractor. With `depth` > 0 every string is rewritten to exactly
/// that length (N^depth strings, the seed's max_no_of_iterations) and applied to the start
/// point x0 (a fixed point, on A). By default a string is final once its piece fits a pixel
/// (its box M(B) inside one pixel: x0's image, with the whole mass) or is smaller than a pixel
/// (the images of a few attractor points spread over it), and dropped when it misses the
/// image. Work splits into jobs by the first strings, each job rewriting its own String_A /
/// String_B pair. Raster: the measure (the mass of a string is the product of its
/// probabilities); points = strings written.
class StringRewriting : public Renderer {
 public:
  std::string name() const override { return "string-rewriting"; }
  std::string description() const override {
    return "string rewriting (5.6): address strings rewritten breadth first and applied to the start point";
  }
  Capabilities capabilities() const override;

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

/// @brief The seed's string rewriting (5.6) over any spelling of the maps: String_A starts as
/// the one-map strings `symbols` (one per map); each of the length - 1 rewrites replaces every
/// string s by symbols[k] + separator + s, k = 0..N-1, in String_B (the seed's
/// new_string = w@string(k)@STR_J: the new map in front), which then overwrites String_A. The
/// N^length strings come by the old string, then the new map. Callers bound the count.
std::vector<std::string> rewrite_map_strings(const std::vector<std::string>& symbols,
                                             const std::string& separator, int length);

}  // namespace ifsforge
