// The random-iteration volume's chain lanes for AVX2 (compiled with -mavx2 -mfma whatever the
// library's flags; run only where the CPU has both): four chains per register, two in flight. The
// orbits and the kernel are voxel_chains_kernel.h's on the chaos game's registers
// (render/chaos_chains_avx2.h); below, each lane's voxel and levels. It includes nothing of the
// library but the chain lanes' headers, and its helpers have internal linkage.
#include "voxel_chains.h"

#if defined(__AVX2__) && defined(__FMA__)
#include "../render/chaos_chains_avx2.h"

namespace ifsforge::chains {
namespace {

/// The grid's voxels and the channels' levels, four lanes at once.
struct Voxels {
  __m256d origin[3], size, dims[3], zero;

  explicit Voxels(const VoxelJob& job) : size(_mm256_set1_pd(job.voxel_size)), zero(_mm256_setzero_pd()) {
    for (int a = 0; a < 3; ++a) {
      origin[a] = _mm256_set1_pd(job.origin[a]);
      dims[a] = _mm256_set1_pd(job.dims[a]);
    }
  }

  /// Each lane's key as VoxelGrid::voxel_of gives it ((x - origin) / size per axis, in [0, dims)
  /// by ordered compares, truncated), kOffGrid where it is off the grid; true where any lane is.
  bool store_keys(std::uint64_t* to, const __m256d* p) const {
    __m256d inside = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    __m256i key = _mm256_setzero_si256();
    for (int a = 0; a < 3; ++a) {
      const __m256d u = _mm256_div_pd(_mm256_sub_pd(p[a], origin[a]), size);
      inside = _mm256_and_pd(inside, _mm256_cmp_pd(u, zero, _CMP_GE_OQ));
      inside = _mm256_and_pd(inside, _mm256_cmp_pd(u, dims[a], _CMP_LT_OQ));
      // Inside, u is in [0, 2^21): its truncation to 32 bits is voxel_of's.
      const __m256i index = _mm256_cvtepu32_epi64(_mm256_cvttpd_epi32(u));
      key = _mm256_or_si256(_mm256_slli_epi64(key, kVoxelKeyBits), index);
    }
    const __m256i off = _mm256_set1_epi64x(static_cast<long long>(kOffGrid));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(to), _mm256_blendv_epi8(off, key, _mm256_castpd_si256(inside)));
    return _mm256_movemask_pd(inside) != 0xF;
  }
  /// Levels below 2^31, truncated.
  void store_level(std::uint64_t* to, __m256d x) const {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(to), _mm256_cvtepu32_epi64(_mm256_cvttpd_epi32(x)));
  }
};

}  // namespace
}  // namespace ifsforge::chains

#include "voxel_chains_kernel.h"

namespace ifsforge::chains {
bool run_voxels_avx2(const Maps& m, const VoxelJob& job) { return run_voxel_lanes(m, job); }
}  // namespace ifsforge::chains

#else  // not x86-64: the host never picks this

namespace ifsforge::chains {
bool run_voxels_avx2(const Maps&, const VoxelJob&) { return false; }
}  // namespace ifsforge::chains

#endif
