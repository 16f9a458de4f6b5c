// The random-iteration volume's chain lanes for AVX-512 (compiled with -mavx512f -mavx512vl
// whatever the library's flags; run only where the CPU has both): eight chains per register. The
// orbits and the kernel are voxel_chains_kernel.h's on the chaos game's registers
// (render/chaos_chains_avx512.h); below, each lane's voxel and levels. It includes nothing of the
// library but the chain lanes' headers, and its helpers have internal linkage.
#include "voxel_chains.h"

#if defined(__AVX512F__) && defined(__AVX512VL__)
#include "../render/chaos_chains_avx512.h"

namespace ifsforge::chains {
namespace {

/// The grid's voxels and the channels' levels, eight lanes at once.
struct Voxels {
  __m512d origin[3], size, dims[3], zero;

  explicit Voxels(const VoxelJob& job) : size(_mm512_set1_pd(job.voxel_size)), zero(_mm512_setzero_pd()) {
    for (int a = 0; a < 3; ++a) {
      origin[a] = _mm512_set1_pd(job.origin[a]);
      dims[a] = _mm512_set1_pd(job.dims[a]);
    }
  }

  /// Each lane's key as VoxelGrid::voxel_of gives it ((x - origin) / size per axis, in [0, dims)
  /// by ordered compares, truncated), kOffGrid where it is off the grid; true where any lane is.
  bool store_keys(std::uint64_t* to, const __m512d* p) const {
    __mmask8 inside = 0xFF;
    __m512i key = _mm512_setzero_si512();
    for (int a = 0; a < 3; ++a) {
      const __m512d u = _mm512_div_pd(_mm512_sub_pd(p[a], origin[a]), size);
      inside = _mm512_mask_cmp_pd_mask(inside, u, zero, _CMP_GE_OQ);
      inside = _mm512_mask_cmp_pd_mask(inside, u, dims[a], _CMP_LT_OQ);
      // Inside, u is in [0, 2^21): its truncation to 32 bits is voxel_of's.
      const __m512i index = _mm512_cvtepu32_epi64(_mm512_cvttpd_epi32(u));
      key = _mm512_or_si512(_mm512_slli_epi64(key, kVoxelKeyBits), index);
    }
    _mm512_storeu_si512(to, _mm512_mask_blend_epi64(inside, _mm512_set1_epi64(static_cast<long long>(kOffGrid)), key));
    return inside != 0xFF;
  }
  /// Levels below 2^31, truncated.
  void store_level(std::uint64_t* to, __m512d x) const {
    _mm512_storeu_si512(to, _mm512_cvtepu32_epi64(_mm512_cvttpd_epi32(x)));
  }
};

}  // namespace
}  // namespace ifsforge::chains

#include "voxel_chains_kernel.h"

namespace ifsforge::chains {
bool run_voxels_avx512(const Maps& m, const VoxelJob& job) { return run_voxel_lanes(m, job); }
}  // namespace ifsforge::chains

#else  // not x86-64: the host never picks this

namespace ifsforge::chains {
bool run_voxels_avx512(const Maps&, const VoxelJob&) { return false; }
}  // namespace ifsforge::chains

#endif
