// The chaos game's cost per point for each kind of system, against the gray 3-map triangle (2D)
// or the tetrahedron (3D): colour systems (channels carried; the fern's maps differ in their
// linear parts, the triangle's share theirs), more than 8 maps (the triangle's
// maps three times over: the same attractor), the 20-map Menger sponge and recurrent systems.
// CPU nanoseconds per point of one thread at 1024² (the render's fixed cost taken out, and
// shown). A plain program, run from the repository's root: it reads the systems from
// samples/systems.
//
//   build/cpp/bench/bench_chaos_paths [--points 3e7] [--repeat 3] [--samples DIR] [--only TEXT] [--size 1024]
// (--size 128: the counters stay in the core's caches, leaving the cost of the arithmetic)
//   /usr/bin/python3 cpp/bench/results.py bench_chaos_paths --plain   # written to RESULTS.md
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_timing.h"
#include "ifsforge/io/ifs_json.h"
#include "ifsforge/render/renderer.h"

using namespace ifsforge;

namespace {

/// The triangle's maps `copies` times over, uniform: the same attractor, copies * 3 maps.
Ifs repeated(const Ifs& ifs, int copies) {
  std::vector<AffineMap> maps;
  for (int k = 0; k < copies; ++k)
    for (std::size_t i = 0; i < ifs.size(); ++i) maps.push_back(ifs.map(i));
  return Ifs(ifs.name() + " x" + std::to_string(copies), ifs.layout(), maps,
             std::vector<double>(maps.size(), 1.0));
}

struct Case {
  std::string label;
  Ifs ifs;
  bool reference;  ///< the row the following rows are measured against
};

}  // namespace

int main(int argc, char** argv) {
  if (bench::flag(argc, argv, "help")) {
    std::puts("bench_chaos_paths [--points P (3e7)] [--repeat R (3)] [--samples DIR] [--only TEXT] [--size S (1024)]");
    return 0;
  }
  const auto points = static_cast<std::uint64_t>(std::stod(bench::option(argc, argv, "points", "3e7")));
  const int repeat = std::stoi(bench::option(argc, argv, "repeat", "3"));
  const std::string dir = bench::option(argc, argv, "samples", "samples/systems");
  const std::string only = bench::option(argc, argv, "only", "");
  const int size = std::stoi(bench::option(argc, argv, "size", "1024"));  // the rows whose label has it, and their references
  auto sample = [&](const char* name) { return read_ifs_json(dir + "/" + name + ".json"); };
  const Ifs triangle = sample("sierpinski_triangle");
  const std::vector<Case> cases = {
      {"gray triangle, 3 maps (2D reference)", triangle, true},
      {"colour triangle, xy+rgb (colour5d_sierpinski_rgb)", sample("colour5d_sierpinski_rgb"), false},
      {"colour fern, xy+hsi, 4 maps of their own linear parts (colour5d_fern_hsi)", sample("colour5d_fern_hsi"), false},
      {"triangle, 9 maps (its maps three times)", repeated(triangle, 3), false},
      {"recurrent squares, 4 maps (recurrent_squares)", sample("recurrent_squares"), false},
      {"tetrahedron, 4 maps, 3D view (3D reference)", sample("sierpinski_tetrahedron"), true},
      {"Menger sponge, 20 maps, 3D view", sample("menger_sponge"), false},
      {"recurrent cubes, 3D view (recurrent_cubes)", sample("recurrent_cubes"), false},
  };

  std::printf("CPU nanoseconds per point, one thread, a %d² image, %.3g points per render less the "
              "render's fixed cost (a 1,024-point render's), best of %d rounds that take every row in turn; the ratio is to the reference row above it (target: at most 2×).\n\n",
              size, double(points), repeat);
  std::printf("| system | maps | fixed CPU ms | CPU ns per point | × reference |\n| --- | ---: | ---: | ---: | ---: |\n");
  // Rounds interleave the rows (every row once a round, best of the rounds per row), so a slow
  // spell of a shared machine falls on rows alike instead of on one row and its ratio.
  std::vector<const Case*> rows;
  for (const Case& c : cases)
    if (c.reference || c.label.find(only) != std::string::npos) rows.push_back(&c);
  std::vector<double> fixed(rows.size(), 1e300), whole(rows.size(), 1e300);
  for (int round = 0; round < repeat; ++round)
    for (std::size_t i = 0; i < rows.size(); ++i) {
      auto cpu_seconds = [&](std::uint64_t n) {
        RenderOptions o;
        o.width = o.height = size;
        o.iterations = n;
        o.threads = 1;
        if (rows[i]->ifs.spatial_dims() == 3) o.view = View{30, 20};
        return bench::best_of(1, [&] { (void)renderer("chaos").render(rows[i]->ifs, o); }).cpu;
      };
      // The render's fixed cost (framing, the channels' bounds, buffers, the finish) measured with
      // 1,024 points and taken out: what is left is the cost of the points.
      fixed[i] = std::min(fixed[i], cpu_seconds(1024));
      whole[i] = std::min(whole[i], cpu_seconds(points));
    }
  double reference = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double ns = (whole[i] - fixed[i]) * 1e9 / double(points);
    if (rows[i]->reference) reference = ns;
    std::printf("| %s | %zu | %.0f | %.2f | %.2f× |\n", rows[i]->label.c_str(), rows[i]->ifs.size(), fixed[i] * 1e3,
                ns, ns / reference);
  }
  return 0;
}
