// Vector IFS benchmarks against their targets: 1 M instances generated (< 0.2 s), a 1 M-
// instance POV-Ray scene written (< 1 s), plus the TSA, the glTF and the SVG writers. The
// POV-Ray parse comparison with a hand-written union is cpp/bench/bench_vector_povray.py.
// Run: build/cpp/bench/bench_vector
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>

#include "ifsforge/io/gltf_instances.h"
#include "ifsforge/io/pov_instances.h"
#include "ifsforge/io/svg.h"
#include "ifsforge/vector/addresses.h"
#include "ifsforge/io/primitive_spec.h"
#include "ifsforge/vector/instances.h"

using namespace ifsforge;

namespace {

/// The Sierpinski tetrahedron with a twist per map: 4^10 = 1,048,576 instances at depth 10.
Ifs tetrahedron() {
  const double corners[4][3] = {{0, 0, 0}, {0.5, 0, 0}, {0.25, 0.433, 0}, {0.25, 0.144, 0.408}};
  std::vector<AffineMap> maps;
  for (int i = 0; i < 4; ++i) {
    const double a = 0.3 * i, c = 0.5 * std::cos(a), s = 0.5 * std::sin(a);
    maps.emplace_back(3, std::vector<double>{c, -s, 0, s, c, 0, 0, 0, 0.5},
                      std::vector<double>{corners[i][0], corners[i][1], corners[i][2]});
  }
  return Ifs("tetrahedron", ChannelLayout("xyz"), maps, {1, 1, 1, 1});
}

Ifs carpet() {
  std::vector<AffineMap> maps;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != 1 || j != 1) maps.emplace_back(2, std::vector<double>{1.0 / 3, 0, 0, 1.0 / 3}, std::vector<double>{i / 3.0, j / 3.0});
  return Ifs("carpet", ChannelLayout("xy"), maps, std::vector<double>(8, 1.0));
}

const InstanceList& million() {
  static const InstanceList list = [] {
    InstanceOptions o;
    o.depth = 10;
    return instances(tetrahedron(), o);
  }();
  return list;
}

std::string scratch(const std::string& name) { return "/tmp/ifsforge_bench_vector_" + std::to_string(getpid()) + name; }

void Instances1M(benchmark::State& state) {
  const Ifs s = tetrahedron();
  InstanceOptions o;
  o.depth = 10;
  o.threads = static_cast<int>(state.range(0));
  std::size_t n = 0;
  for (auto _ : state) n = instances(s, o).size();
  state.counters["instances"] = static_cast<double>(n);
  state.counters["instances/s"] = benchmark::Counter(double(n) * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(Instances1M)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void TesseralSynecdoche1M(benchmark::State& state) {
  const Ifs s = tetrahedron();
  std::size_t n = 0;
  for (auto _ : state) n = tesseral_synecdoche(s, 10, 0.0, {}, static_cast<int>(state.range(0))).addresses.size();
  state.counters["leaves"] = static_cast<double>(n);
}
BENCHMARK(TesseralSynecdoche1M)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void WritePovScene1M(benchmark::State& state) {
  const InstanceList& list = million();
  const std::string path = scratch(".pov");
  PovSceneOptions o;
  o.threads = static_cast<int>(state.range(0));
  for (auto _ : state) write_pov_scene(path, list, o);
  std::FILE* f = std::fopen(path.c_str(), "rb");
  std::fseek(f, 0, SEEK_END);
  state.counters["bytes"] = static_cast<double>(std::ftell(f));
  std::fclose(f);
  std::remove(path.c_str());
}
BENCHMARK(WritePovScene1M)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void WriteGltf100k(benchmark::State& state) {
  InstanceOptions io;
  io.depth = 8;  // 65,536 instances
  io.primitives = {parse_primitive("cone")};
  const InstanceList list = instances(tetrahedron(), io);
  const std::string path = scratch(".glb");
  for (auto _ : state) write_gltf_instances(path, list);
  state.counters["instances"] = static_cast<double>(list.size());
  std::remove(path.c_str());
}
BENCHMARK(WriteGltf100k)->Unit(benchmark::kMillisecond)->UseRealTime();

void WriteSvgCarpet(benchmark::State& state) {
  InstanceOptions io;
  io.depth = 6;  // 262,144 squares
  io.primitives = {parse_primitive("square")};
  const InstanceList list = instances(carpet(), io);
  const std::string path = scratch(".svg");
  for (auto _ : state) write_svg(path, list);
  state.counters["instances"] = static_cast<double>(list.size());
  std::remove(path.c_str());
}
BENCHMARK(WriteSvgCarpet)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
