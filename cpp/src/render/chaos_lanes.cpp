// Which lane kernel runs: chosen per render from the CPU (and IFSFORGE_ISA), so one binary built
// for any x86-64 still takes the widest kernel the CPU has; and whether large images are
// counted through tiles, and whether the general path counts into narrow counters.
#include <cstdlib>
#include <cstring>

#include "chaos_lanes.h"
#include "ifsforge/core/error.h"

namespace ifsforge::lanes {
namespace {

bool cpu_has_avx2() {
#if defined(__x86_64__) || defined(__i386__)
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
#else
  return false;
#endif
}

/// The chain lanes' AVX-512 kernel (chaos_chains_avx512.cpp) needs AVX-512 F and VL.
bool cpu_has_avx512() {
#if defined(__x86_64__) || defined(__i386__)
  static const bool has = cpu_has_avx2() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
  return has;
#else
  return false;
#endif
}

}  // namespace

const char* lane_isa() {
  const char* forced = std::getenv("IFSFORGE_ISA");
  if (forced && *forced) {
    if (std::strcmp(forced, "baseline") == 0) return "baseline";
    if (std::strcmp(forced, "avx512") == 0) {
      if (!cpu_has_avx512()) throw InputError("IFSFORGE_ISA=avx512, but this CPU lacks AVX-512 F and VL");
      return "avx512";
    }
    if (std::strcmp(forced, "avx2") != 0)
      throw InputError("IFSFORGE_ISA must be baseline, avx2 or avx512, not " + std::string(forced));
    if (!cpu_has_avx2()) throw InputError("IFSFORGE_ISA=avx2, but this CPU lacks AVX2 or FMA");
    return "avx2";
  }
  return cpu_has_avx512() ? "avx512" : cpu_has_avx2() ? "avx2" : "baseline";
}

bool lane_tiles() {
  const char* tiles = std::getenv("IFSFORGE_CHAOS_TILES");
  return !(tiles && std::strcmp(tiles, "0") == 0);
}

bool narrow_counters() {
  const char* narrow = std::getenv("IFSFORGE_CHAOS_NARROW");
  return !(narrow && std::strcmp(narrow, "0") == 0);
}

Kernel lane_kernel(int n) {
  // The float lanes have no AVX-512 kernel: where the chain lanes take theirs, these take AVX2.
  const bool wide = std::strcmp(lane_isa(), "baseline") != 0;
  if (n == 2) return wide ? run_avx2_2 : run_baseline2;
  return wide ? run_avx2_3 : run_baseline3;
}

}  // namespace ifsforge::lanes
