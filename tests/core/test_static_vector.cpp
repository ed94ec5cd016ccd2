#include <doctest/doctest.h>

#include <random>
#include <vector>

#include "itp/core/static_vector.hpp"

using itp::StaticVector;

TEST_CASE("StaticVector refuses to grow past its capacity") {
  StaticVector<int, 3> v;
  CHECK(v.push_back(1));
  CHECK(v.push_back(2));
  CHECK(v.push_back(3));
  CHECK(v.full());
  CHECK_FALSE(v.push_back(4));
  CHECK(v.size() == 3);
  CHECK(v.back() == 3);
  CHECK_FALSE(v.resize(4));
  CHECK(v.resize(1));
  CHECK(v.size() == 1);
  CHECK(v[0] == 1);
}

TEST_CASE("StaticVector behaves like std::vector under random operations") {
  std::mt19937 rng(42);
  StaticVector<int, 16> ours;
  std::vector<int> ref;
  for (int step = 0; step < 5000; ++step) {
    const int op = static_cast<int>(rng() % 4);
    if (op <= 1) {
      const int value = static_cast<int>(rng() % 1000);
      const bool pushed = ours.push_back(value);
      CHECK(pushed == (ref.size() < 16));
      if (pushed) {
        ref.push_back(value);
      }
    } else if (op == 2 && !ref.empty()) {
      ours.pop_back();
      ref.pop_back();
    } else if (op == 3 && rng() % 10 == 0) {
      ours.clear();
      ref.clear();
    }
    REQUIRE(ours.size() == ref.size());
    CHECK(std::vector<int>(ours.begin(), ours.end()) == ref);
  }
}

TEST_CASE("StaticVector exposes a capacity-free span") {
  StaticVector<double, 8> v;
  REQUIRE(v.push_back(1.5));
  REQUIRE(v.push_back(2.5));
  std::span<const double> s = v.span();
  CHECK(s.size() == 2);
  CHECK(s[1] == doctest::Approx(2.5));
}

namespace {

// An ordinary function (no template on the capacity) that fills any
// StaticVector through its capacity-free base.
int fill_squares(itp::VectorBase<int>& v, int count) {
  v.clear();
  int pushed = 0;
  for (int i = 0; i < count; ++i) {
    if (!v.push_back(i * i)) break;
    ++pushed;
  }
  return pushed;
}

}  // namespace

TEST_CASE("VectorBase: one non-template function fills vectors of any capacity") {
  StaticVector<int, 3> small;
  StaticVector<int, 8> large;
  CHECK(fill_squares(small, 5) == 3);
  CHECK(fill_squares(large, 5) == 5);
  CHECK(small.capacity() == 3);
  CHECK(static_cast<itp::VectorBase<int>&>(large).capacity() == 8);
  CHECK(std::vector<int>(large.begin(), large.end()) == std::vector<int>{0, 1, 4, 9, 16});
  // Assigning across capacities through the base cuts to the target's.
  itp::VectorBase<int>& small_base = small;
  CHECK_FALSE(small_base.assign(large));
  CHECK(std::vector<int>(small.begin(), small.end()) == std::vector<int>{0, 1, 4});
}

TEST_CASE("StaticVector copies own their storage: changing a copy leaves the original") {
  StaticVector<int, 4> a;
  REQUIRE(a.push_back(1));
  REQUIRE(a.push_back(2));
  StaticVector<int, 4> b = a;  // copy construction
  StaticVector<int, 4> c;
  c = a;                       // copy assignment
  b[0] = 10;
  c[1] = 20;
  REQUIRE(b.push_back(3));
  CHECK(a.size() == 2);
  CHECK(a[0] == 1);
  CHECK(a[1] == 2);
  CHECK(b.data() != a.data());
  CHECK(c.data() != a.data());
  CHECK(b[0] == 10);
  CHECK(c[1] == 20);
}
