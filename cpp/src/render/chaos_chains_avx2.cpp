// The chain lanes for AVX2 (compiled with -mavx2 -mfma whatever the library's flags; run only
// where the CPU has both): four chains per register of doubles, two registers in flight. The
// kernel is chaos_chains_kernel.h's, on the registers and operations of chaos_chains_avx2.h; -ffp-contract=off
// keeps the compiler from fusing a multiply and an add, so the bits are the baseline kernel's. It
// includes nothing of the library but chaos_chains.h, and its helpers have internal linkage.
#include "chaos_chains.h"

#if defined(__AVX2__) && defined(__FMA__)
#include "chaos_chains_avx2.h"

#include "chaos_chains_kernel.h"

namespace ifsforge::chains {
void run_avx2(const Maps& m, const Job& job) { run_lanes(m, job); }
}  // namespace ifsforge::chains

#else  // not x86-64: the host never picks this

namespace ifsforge::chains {
void run_avx2(const Maps& m, const Job& job) { run_baseline(m, job); }
}  // namespace ifsforge::chains

#endif
