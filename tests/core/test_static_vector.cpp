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
