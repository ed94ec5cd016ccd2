#include <doctest/doctest.h>

#include <cstdlib>
#include <memory>
#include <vector>

#include "heap_guard.hpp"

using test_support::HeapGuard;

namespace {
// Allocations must escape, or an optimising compiler may elide a malloc/free pair.
void* volatile g_sink = nullptr;
}  // namespace

TEST_CASE("heap guard counts operator new inside its scope") {
  HeapGuard guard(HeapGuard::Mode::kObserveOnly);
  auto p = std::make_unique<int>(7);
  std::vector<double> v(100);
  g_sink = p.get();
  g_sink = v.data();
  CHECK(guard.allocations() == 2);
}

TEST_CASE("heap guard counts malloc and calloc") {
  HeapGuard guard(HeapGuard::Mode::kObserveOnly);
  void* a = std::malloc(16);
  g_sink = a;
  void* b = std::calloc(4, 4);
  g_sink = b;
  std::free(a);
  std::free(b);
  CHECK(guard.allocations() == 2);
}

TEST_CASE("heap guard ignores allocations outside its scope") {
  auto before = std::make_unique<int>(1);
  std::size_t seen = 0;
  {
    HeapGuard guard;  // fails this test if anything below allocates
    int local[8] = {};
    local[3] = *before;
    seen = guard.allocations();
    CHECK(local[3] == 1);
  }
  auto after = std::make_unique<int>(2);
  CHECK(seen == 0);
}
