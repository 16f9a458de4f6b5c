#pragma once
/// @file Large buffers with few page faults. A fresh buffer's first write faults every page in;
/// with 4 KB pages a 64 MB raster takes 16,384 faults, each costly on a virtual machine, with
/// transparent huge pages 32. The kernel gives huge pages only to ranges
/// advised MADV_HUGEPAGE (the usual "madvise" setting), before their first touch.
#include <cstddef>
#include <iterator>
#include <type_traits>
#include <utility>
#include <vector>

#include "ifsforge/core/progress.h"

namespace ifsforge {

/// @brief Advises transparent huge pages for the 2 MB-aligned part of [data, data + bytes)
/// when the range holds at least two of them; a no-op for small ranges and off Linux.
void advise_huge_pages(void* data, std::size_t bytes);

/// @brief Faults the pages of [data, data + bytes) in on every core (Linux 5.14+), for ranges
/// of 8 MB or more; a no-op elsewhere. `poll` hears it (Cancelled when it says stop): a
/// gigabyte takes about a second.
void populate_pages(void* data, std::size_t bytes, const ProgressCallback& poll = {});

/// @brief Storage for `bytes` bytes: from 1 MB up, a 2 MB-aligned private mapping advised
/// huge pages, so that its first touch takes one fault per 2 MB rather than one per 4 KB even
/// at its ends (a malloc'd buffer's unaligned ends fault 4 KB at a time: up to 512 faults for
/// each of a render's rasters); smaller ones from operator new.
void* allocate_pages(std::size_t bytes);
/// @brief Returns what allocate_pages(bytes) gave.
void release_pages(void* data, std::size_t bytes) noexcept;
/// @brief allocate_pages storage whose bytes are all zero: a fresh mapping already is (nothing is
/// written); smaller storage is cleared. Returned by release_pages.
void* allocate_zeroed_pages(std::size_t bytes);

/// An allocator of allocate_pages storage, for the large per-pixel and per-voxel buffers.
template <class T>
struct PageAllocator {
  using value_type = T;
  PageAllocator() = default;
  template <class U>
  PageAllocator(const PageAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocate_pages(n * sizeof(T))); }
  void deallocate(T* data, std::size_t n) noexcept { release_pages(data, n * sizeof(T)); }
  template <class U>
  bool operator==(const PageAllocator<U>&) const noexcept { return true; }
  template <class U>
  bool operator!=(const PageAllocator<U>&) const noexcept { return false; }
};

/// A vector of large storage: rasters, images and per-pixel counters.
template <class T>
using LargeVector = std::vector<T, PageAllocator<T>>;

/// An allocator of allocate_zeroed_pages storage whose elements made without a value are left as
/// they are: zero bytes in a fresh buffer, so sizing one writes nothing (its pages are touched
/// once, by their first real value). Growing after shrinking would show the old elements: only
/// zeroed_large sizes these.
template <class T>
struct ZeroPageAllocator : PageAllocator<T> {
  ZeroPageAllocator() = default;
  template <class U>
  ZeroPageAllocator(const ZeroPageAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocate_zeroed_pages(n * sizeof(T))); }
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

/// Per-pixel counters that start at zero (trivial types whose zero is all zero bytes).
template <class T>
using ZeroedVector = std::vector<T, ZeroPageAllocator<T>>;

/// @brief Makes `v`'s capacity at least `n` elements, keeping its contents; a new buffer is
/// advised huge pages before anything is written to it.
template <class T, class A>
void reserve_large(std::vector<T, A>& v, std::size_t n, const ProgressCallback& poll = {}) {
  if (v.capacity() >= n) return;
  std::vector<T, A> fresh;
  fresh.reserve(n);
  advise_huge_pages(fresh.data(), n * sizeof(T));
  populate_pages(fresh.data(), n * sizeof(T), poll);
  fresh.insert(fresh.end(), std::make_move_iterator(v.begin()), std::make_move_iterator(v.end()));
  v.swap(fresh);
}

/// @brief `v.assign(n, value)` through reserve_large: a buffer that already holds `n` is reused.
template <class T, class A>
void assign_large(std::vector<T, A>& v, std::size_t n, const T& value, const ProgressCallback& poll = {}) {
  if (v.capacity() < n) {
    std::vector<T, A>().swap(v);  // release first: the old and new buffers never coexist
    reserve_large(v, n, poll);
  }
  v.assign(n, value);
}

/// @brief `v` becomes `n` zeros in a fresh buffer (huge pages, faulted in on every core); nothing
/// but the kernel writes them.
template <class T>
void zeroed_large(ZeroedVector<T>& v, std::size_t n, const ProgressCallback& poll = {}) {
  static_assert(std::is_trivial_v<T>, "zeroed_large holds trivial types");
  ZeroedVector<T>().swap(v);  // release first: the old and new buffers never coexist
  reserve_large(v, n, poll);
  v.resize(n);
}

/// @brief `v.resize(n)` (new elements value-initialised) through reserve_large.
template <class T, class A>
void resize_large(std::vector<T, A>& v, std::size_t n, const ProgressCallback& poll = {}) {
  reserve_large(v, n, poll);
  v.resize(n);
}

}  // namespace ifsforge
