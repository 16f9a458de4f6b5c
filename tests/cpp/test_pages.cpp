// Large buffers: 2 MB-aligned storage (so huge pages reach both ends), small ones as usual,
// contents kept through growth, and fault counts that show the huge pages were used.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdint>
#include <fstream>
#include <numeric>
#include <string>

#include "ifsforge/core/pages.h"

using namespace ifsforge;

namespace {
constexpr std::uintptr_t kHuge = std::uintptr_t(2) << 20;

/// Whether the kernel gives transparent huge pages to advised ranges (its setting, not what a
/// test observes: a buffer that lost its huge pages must fail, not pass unchecked).
bool huge_pages_offered() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string setting;
  std::getline(in, setting);
  return setting.find("[always]") != std::string::npos || setting.find("[madvise]") != std::string::npos;
}

long minor_faults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}
}  // namespace

TEST(Pages, LargeBuffersStartOnA2MbBoundaryAndKeepTheirContents) {
  LargeVector<std::uint32_t> v(3 << 18);  // 3 MB
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % kHuge, 0u);
  std::iota(v.begin(), v.end(), 0u);
  v.resize(v.size() * 3);  // grows into a new mapping: the old values move with it
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % kHuge, 0u);
  for (std::uint32_t i = 0; i < (3u << 18); ++i) ASSERT_EQ(v[i], i);
  EXPECT_EQ(v.back(), 0u);

  LargeVector<std::uint8_t> small(1000, 7);  // below 1 MB: operator new, any alignment
  EXPECT_EQ(small[999], 7);
  LargeVector<std::uint8_t> empty;
  assign_large(empty, 0, std::uint8_t(0));
  EXPECT_TRUE(empty.empty());
}

TEST(Pages, AFreshLargeBufferFaultsInFarFewerThanOnePagePer4Kb) {
  // 64 MB written once: 16,384 faults on 4 KB pages; on 2 MB pages 32. Where the kernel offers
  // no huge pages (setting "never", or no such setting) only the contents are checked.
  const long before = minor_faults();
  LargeVector<std::uint8_t> v(std::size_t(64) << 20, 1);
  const long faults = minor_faults() - before;
  if (huge_pages_offered()) {
    EXPECT_LT(faults, 1024) << "the buffer was faulted in 4 KB pages";
  }
  EXPECT_EQ(v.front(), 1);
  EXPECT_EQ(v.back(), 1);
}

TEST(Pages, ZeroedBuffersAreZeroAtEverySizeAndAfterReuse) {
  // Large (a fresh mapping, left as the kernel zeroed it) and small (cleared) storage; then the
  // same vector written over and zeroed again (a fresh buffer, not the old one).
  for (std::size_t n : {std::size_t(1000), std::size_t(3) << 20}) {
    ZeroedVector<std::uint64_t> v;
    zeroed_large(v, n);
    ASSERT_EQ(v.size(), n);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(v[i], 0u) << n << " " << i;
    std::iota(v.begin(), v.end(), std::uint64_t(1));
    zeroed_large(v, n);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(v[i], 0u) << n << " after reuse, " << i;
  }
}
