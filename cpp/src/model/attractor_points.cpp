#include "ifsforge/model/attractor_points.h"

namespace ifsforge {

std::vector<Point> attractor_extremes(const Ifs& ifs) {
  // Each point with the map that placed it: a recurrent system's words follow its transitions
  // (the fixed point of w_i lies on the attractor when w_i may follow itself).
  auto allowed = [&](std::size_t from, std::size_t to) { return !ifs.recurrent() || ifs.transitions()(from, to) > 0.0; };
  // Room for all of them at once: regrowing the vectors (a quarter of a MB) copied them and
  // faulted in fresh pages, in the frame's and the plan's setup before any parallel work.
  constexpr std::size_t kMost = 4096;
  std::vector<Point> points;
  points.reserve(kMost);
  std::vector<std::size_t> placed;
  for (std::size_t i = 0; i < ifs.size(); ++i)
    if (ifs.map(i).contraction_factor() < 1.0 && allowed(i, i))
      if (auto p = ifs.map(i).fixed_point()) {
        points.push_back(*p);
        placed.push_back(i);
      }
  std::vector<Point> level = points;
  std::vector<std::size_t> level_placed = placed;
  while (!level.empty() && points.size() + level.size() * ifs.size() <= kMost) {
    std::vector<Point> next;
    std::vector<std::size_t> next_placed;
    next.reserve(level.size() * ifs.size());
    next_placed.reserve(level.size() * ifs.size());
    for (std::size_t k = 0; k < level.size(); ++k)
      for (std::size_t j = 0; j < ifs.size(); ++j)
        if (allowed(level_placed[k], j)) {
          next.push_back(ifs.map(j)(level[k]));
          next_placed.push_back(j);
        }
    points.insert(points.end(), next.begin(), next.end());
    level.swap(next);
    level_placed.swap(next_placed);
  }
  return points;
}

}  // namespace ifsforge
