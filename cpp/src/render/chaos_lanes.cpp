// Which lane kernel runs: chosen per render from the CPU (and IFSFORGE_ISA), so one binary built
// for any x86-64 still takes the wide kernel where the CPU has it; and whether large images are
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

}  // namespace

const char* lane_isa() {
  const char* forced = std::getenv("IFSFORGE_ISA");
  if (forced && *forced) {
    if (std::strcmp(forced, "baseline") == 0) return "baseline";
    if (std::strcmp(forced, "avx2") != 0) throw InputError("IFSFORGE_ISA must be baseline or avx2, not " + std::string(forced));
    if (!cpu_has_avx2()) throw InputError("IFSFORGE_ISA=avx2, but this CPU lacks AVX2 or FMA");
    return "avx2";
  }
  return cpu_has_avx2() ? "avx2" : "baseline";
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
  const bool wide = std::strcmp(lane_isa(), "avx2") == 0;
  if (n == 2) return wide ? run_avx2_2 : run_baseline2;
  return wide ? run_avx2_3 : run_baseline3;
}

}  // namespace ifsforge::lanes
