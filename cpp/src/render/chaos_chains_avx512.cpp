// The chain lanes for AVX-512 (compiled with -mavx512f -mavx512vl whatever the library's flags;
// run only where the CPU has both): eight chains per register of doubles, one register, so each
// step of eight chains takes half the AVX2 kernel's instructions, and up to eight maps' offsets
// and coefficients come from registers (a permute each). The kernel is chaos_chains_kernel.h's,
// on the registers and operations of chaos_chains_avx512.h: each the same IEEE operation per lane as the AVX2 ones
// (-ffp-contract=off: no multiply and add fused), so the bits are the baseline kernel's. It
// includes nothing of the library but chaos_chains.h, and its helpers have internal linkage.
#include "chaos_chains.h"

#if defined(__AVX512F__) && defined(__AVX512VL__)
#include "chaos_chains_avx512.h"

#include "chaos_chains_kernel.h"

namespace ifsforge::chains {
void run_avx512(const Maps& m, const Job& job) { run_lanes(m, job); }
}  // namespace ifsforge::chains

#else  // not x86-64: the host never picks this

namespace ifsforge::chains {
void run_avx512(const Maps& m, const Job& job) { run_baseline(m, job); }
}  // namespace ifsforge::chains

#endif
