#include "heap_guard.hpp"

#include <doctest/doctest.h>

#include <cstdlib>
#include <new>

namespace {
thread_local int t_armed = 0;            // guards alive on this thread
thread_local std::size_t t_count = 0;    // allocations while armed
thread_local std::size_t t_bytes = 0;    // bytes they requested

void note_allocation(std::size_t bytes) {
  if (t_armed > 0) {
    ++t_count;
    t_bytes += bytes;
  }
}

void* checked(void* p) {
  if (p == nullptr) {
    throw std::bad_alloc();
  }
  return p;
}
}  // namespace

namespace test_support {

HeapGuard::HeapGuard(Mode mode) : mode_(mode), start_(t_count), start_bytes_(t_bytes) { ++t_armed; }

HeapGuard::~HeapGuard() {
  --t_armed;
  if (mode_ == Mode::kFailOnAllocation) {
    CHECK_MESSAGE(t_count == start_, "heap allocation inside a HeapGuard scope");
  }
}

std::size_t HeapGuard::allocations() const { return t_count - start_; }

std::size_t HeapGuard::bytes() const { return t_bytes - start_bytes_; }

}  // namespace test_support

// The C allocator, reached through the linker's --wrap (see tests/CMakeLists.txt).
extern "C" {
void* __real_malloc(std::size_t);
void* __real_calloc(std::size_t, std::size_t);
void* __real_realloc(void*, std::size_t);
void* __real_aligned_alloc(std::size_t, std::size_t);
int __real_posix_memalign(void**, std::size_t, std::size_t);

void* __wrap_malloc(std::size_t n) {
  note_allocation(n);
  return __real_malloc(n);
}
void* __wrap_calloc(std::size_t n, std::size_t size) {
  note_allocation(n * size);
  return __real_calloc(n, size);
}
void* __wrap_realloc(void* p, std::size_t n) {
  note_allocation(n);
  return __real_realloc(p, n);
}
void* __wrap_aligned_alloc(std::size_t align, std::size_t n) {
  note_allocation(n);
  return __real_aligned_alloc(align, n);
}
int __wrap_posix_memalign(void** p, std::size_t align, std::size_t n) {
  note_allocation(n);
  return __real_posix_memalign(p, align, n);
}
}

// operator new in all its forms (counted once here, so they take memory from
// __real_malloc directly); the matching deletes go straight to free().
void* operator new(std::size_t n) {
  note_allocation(n);
  return checked(__real_malloc(n == 0 ? 1 : n));
}
void* operator new[](std::size_t n) {
  note_allocation(n);
  return checked(__real_malloc(n == 0 ? 1 : n));
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  note_allocation(n);
  return __real_malloc(n == 0 ? 1 : n);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  note_allocation(n);
  return __real_malloc(n == 0 ? 1 : n);
}
void* operator new(std::size_t n, std::align_val_t a) {
  note_allocation(n);
  void* p = nullptr;
  return checked(__real_posix_memalign(&p, static_cast<std::size_t>(a), n == 0 ? 1 : n) == 0 ? p : nullptr);
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return operator new(n, a);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
