#include "ifsforge/model/attractor_points.h"

namespace ifsforge {

std::vector<Point> attractor_extremes(const Ifs& ifs) {
  std::vector<Point> points;
  for (const auto& m : ifs.maps())
    if (m.contraction_factor() < 1.0)
      if (auto p = m.fixed_point()) points.push_back(*p);
  std::vector<Point> level = points;
  while (!level.empty() && points.size() + level.size() * ifs.size() <= 4096) {
    std::vector<Point> next;
    for (const Point& p : level)
      for (const auto& m : ifs.maps()) next.push_back(m(p));
    points.insert(points.end(), next.begin(), next.end());
    level.swap(next);
  }
  return points;
}

}  // namespace ifsforge
