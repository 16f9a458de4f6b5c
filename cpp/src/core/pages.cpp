#include "ifsforge/core/pages.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <new>

#include "ifsforge/core/parallel.h"

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace ifsforge {

void advise_huge_pages(void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t(2) << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHuge - 1);
  // Advice only: a kernel without transparent huge pages refuses it and nothing changes.
  if (last >= first + 2 * kHuge) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
constexpr std::size_t kPagedFrom = std::size_t(1) << 20;
#if defined(__linux__)
constexpr bool kMapped = true;  // allocate_pages maps from kPagedFrom up
#else
constexpr bool kMapped = false;
#endif
std::size_t mapped_length(std::size_t bytes) { return (bytes + kHugePage - 1) & ~(kHugePage - 1); }
}  // namespace

void* allocate_pages(std::size_t bytes) {
#if defined(__linux__)
  if (bytes >= kPagedFrom) {
    // Map 2 MB more than needed and keep the aligned middle: the kernel can back it with huge
    // pages from its first byte to its last.
    const std::size_t length = mapped_length(bytes);
    if (length < bytes) throw std::bad_alloc();
    void* raw = mmap(nullptr, length + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const auto begin = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t aligned = (begin + kHugePage - 1) & ~std::uintptr_t(kHugePage - 1);
    if (aligned > begin) munmap(raw, aligned - begin);
    if (const std::uintptr_t tail = begin + kHugePage - aligned; tail > 0)
      munmap(reinterpret_cast<void*>(aligned + length), tail);
#ifdef MADV_HUGEPAGE
    madvise(reinterpret_cast<void*>(aligned), length, MADV_HUGEPAGE);  // advice: refused, nothing changes
#endif
    return reinterpret_cast<void*>(aligned);
  }
#endif
  return ::operator new(bytes);
}

void* allocate_zeroed_pages(std::size_t bytes) {
  void* data = allocate_pages(bytes);
  if (bytes < kPagedFrom || !kMapped) std::memset(data, 0, bytes);  // a fresh mapping is zero already
  return data;
}

void release_pages(void* data, std::size_t bytes) noexcept {
#if defined(__linux__)
  if (bytes >= kPagedFrom) {
    munmap(data, mapped_length(bytes));
    return;
  }
#endif
  ::operator delete(data);
}

void populate_pages(void* data, std::size_t bytes, const ProgressCallback& poll) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  // The kernel zeroes each fresh page on the thread that first writes it, so a serial fill of a
  // large buffer pays for every page on one core. Faulted in ahead on every core, in 4 MB pieces
  // (fixed, so the split does not depend on the thread count; it changes no byte anyway), from
  // 8 MB: below that the threads cost more than the faults.
  constexpr std::uintptr_t kPage = 4096, kPiece = std::uintptr_t(4) << 20;
  if (bytes < 2 * kPiece) return;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kPage - 1) & ~(kPage - 1), last = (begin + bytes) & ~(kPage - 1);
  const std::size_t pieces = (last - first + kPiece - 1) / kPiece;
  parallel_jobs(pieces, 0, [&](std::size_t k, int) {
    const std::uintptr_t from = first + k * kPiece, to = std::min(last, from + kPiece);
    madvise(reinterpret_cast<void*>(from), to - from, MADV_POPULATE_WRITE);  // a no-op where unsupported
  }, poll);
#else
  (void)data;
  (void)bytes;
  (void)poll;
#endif
}

}  // namespace ifsforge
