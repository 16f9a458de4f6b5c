#pragma once
// The instruction sets this CPU runs, as IFSFORGE_ISA names them (render/chaos_lanes.h's
// lane_isa): suites that compare the kernels render with each in turn.
#include <vector>

namespace ifsforge::instruction_sets {

/// "baseline", then "avx2" and "avx512" where the CPU has them (AVX2 with FMA; AVX-512 F and VL).
inline std::vector<const char*> available() {
  std::vector<const char*> sets = {"baseline"};
#if defined(__x86_64__)
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (avx2) sets.push_back("avx2");
  if (avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl")) sets.push_back("avx512");
#endif
  return sets;
}

}  // namespace ifsforge::instruction_sets
