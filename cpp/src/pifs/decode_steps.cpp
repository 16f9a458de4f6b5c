#include "decode_steps.h"

#include <algorithm>

#include "ifsforge/pifs/decoder.h"
#include "ifsforge/pifs/planes.h"

namespace ifsforge {

PlaneDecodeSteps::PlaneDecodeSteps(const PifsCode& code, const PifsPlane& plane, std::size_t part_pixels)
    : code_(code), plane_(plane), part_pixels_(std::max<std::size_t>(1, part_pixels)) {
  // decode_plane's hierarchical decode at scale 1: the coarsest level iterated to its fixed
  // point here (a small raster), the doublings as stages.
  const int pw = code.padded(plane.width), ph = code.padded(plane.height), coarsest = -code.min_log;
  PifsRaster x = plane_raster(scaled_length(pw, coarsest), scaled_length(ph, coarsest), 128.f);
  PifsRaster next = plane_raster(x.width, x.height, 128.f);
  for (int i = 0; i < kDefaultIterations; ++i) {
    apply_leaves(code, plane, coarsest, x, false, next, 0, plane.leaves.size());
    std::swap(x, next);
  }
  levels_.push_back(std::move(x));
  for (int l = coarsest + 1; l <= 0; ++l) levels_.push_back(plane_raster(scaled_length(pw, l), scaled_length(ph, l), 0.f));
}

std::size_t PlaneDecodeSteps::parts(const PifsRaster& r) const {
  const std::size_t by_size = std::size_t(r.width) * std::size_t(r.height) / part_pixels_;
  return std::clamp<std::size_t>(by_size, 1, std::max<std::size_t>(1, plane_.leaves.size()));
}

std::vector<std::size_t> PlaneDecodeSteps::stages() const {
  std::vector<std::size_t> out;
  for (std::size_t i = 1; i < levels_.size(); ++i) out.push_back(parts(levels_[i]));
  out.push_back(parts(levels_.back()));  // the vertical edges
  out.push_back(parts(levels_.back()));  // the horizontal edges
  return out;
}

void PlaneDecodeSteps::run(std::size_t stage, std::size_t part) {
  const std::size_t count = plane_.leaves.size(), passes = levels_.size() - 1;
  const std::size_t parts_here = parts(stage < passes ? levels_[stage + 1] : levels_.back());
  const std::size_t begin = count * part / parts_here, end = count * (part + 1) / parts_here;
  if (stage < passes) {
    const int l = -code_.min_log + int(stage) + 1;
    apply_leaves(code_, plane_, l, levels_[stage], true, levels_[stage + 1], begin, end);
  } else {
    deblock_leaves(code_, plane_, 0, levels_.back(), stage == passes, begin, end);
  }
}

}  // namespace ifsforge
