#pragma once
// Proves "no heap": counts every allocation made through operator new or the
// C allocator (malloc, calloc, realloc, aligned_alloc, posix_memalign) while a
// guard is alive on this thread. A guard in kFailOnAllocation mode fails the
// current doctest test from its destructor if anything was allocated.
#include <cstddef>

namespace test_support {

class HeapGuard {
 public:
  enum class Mode { kFailOnAllocation, kObserveOnly };

  explicit HeapGuard(Mode mode = Mode::kFailOnAllocation);
  ~HeapGuard();
  HeapGuard(const HeapGuard&) = delete;
  HeapGuard& operator=(const HeapGuard&) = delete;

  // Allocations seen since this guard was created.
  std::size_t allocations() const;
  // Bytes requested by them (a reader that allocates what a header claims
  // shows up here even when the memory is never touched).
  std::size_t bytes() const;

 private:
  Mode mode_;
  std::size_t start_;
  std::size_t start_bytes_;
};

}  // namespace test_support
