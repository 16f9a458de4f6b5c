// Linked into every fuzz target: operator new throws std::bad_alloc above 2 GB, as it does in a
// release build once the machine's memory runs out, so the readers' handling of absurd declared
// sizes is what gets tested (ASan's own operator new aborts the process instead). malloc and
// free stay ASan's, so leaks and overflows are still caught.
#include <cstdlib>
#include <new>

namespace {
constexpr std::size_t kLimit = std::size_t(2) << 30;

void* allocate(std::size_t n) {
  if (n > kLimit) throw std::bad_alloc();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return n > kLimit ? nullptr : std::malloc(n ? n : 1); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return n > kLimit ? nullptr : std::malloc(n ? n : 1); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
