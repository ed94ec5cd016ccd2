#include <doctest/doctest.h>

#include <cstdint>
#include <random>

#include "itp/core/work_ledger.hpp"

using itp::WorkLedger;

TEST_CASE("WorkLedger grants the most iterations that fit, and nothing when one does not") {
  WorkLedger w;
  w.begin(1000);
  CHECK(w.grant(100, 30, 60) == 30);   // (1000 - 100) / 30
  CHECK(w.grant(100, 30, 12) == 12);   // the caller's cap
  CHECK(w.grant(971, 30, 60) == 0);    // setup fits, one iteration does not
  CHECK(w.grant(970, 30, 60) == 1);
  CHECK(w.grant(100, 30, 0) == 0);
  w.charge(100, 30, 25);               // 850 spent
  CHECK(w.left() == 150);
  CHECK(w.grant(100, 30, 60) == 1);
  CHECK(w.grant(130, 30, 60) == 0);
}

TEST_CASE("WorkLedger: whatever the mix of solves, the work booked never exceeds the budget (brute force)") {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const std::int32_t budget = std::uniform_int_distribution<std::int32_t>(0, 30000)(rng);
    WorkLedger w;
    w.begin(budget);
    std::int64_t booked = 0;  // summed here, independently of the ledger
    for (int solve = 0; solve < 60; ++solve) {
      const std::int32_t setup = std::uniform_int_distribution<std::int32_t>(1, 800)(rng);
      const std::int32_t per = std::uniform_int_distribution<std::int32_t>(1, 50)(rng);
      const int cap = std::uniform_int_distribution<int>(0, 300)(rng);
      const int granted = w.grant(setup, per, cap);
      REQUIRE(granted >= 0);
      REQUIRE(granted <= cap);
      if (granted == 0) {
        // Nothing granted: not even one iteration fits, or the cap is 0.
        CHECK((cap == 0 || booked + setup + per > budget));
        continue;
      }
      // The grant is the largest that fits: one more would not (or the cap).
      CHECK(booked + setup + static_cast<std::int64_t>(per) * granted <= budget);
      CHECK((granted == cap || booked + setup + static_cast<std::int64_t>(per) * (granted + 1) > budget));
      const int used = std::uniform_int_distribution<int>(0, granted)(rng);  // a QP may converge early
      w.charge(setup, per, used);
      booked += setup + static_cast<std::int64_t>(per) * used;
      REQUIRE(booked <= budget);
      CHECK(w.left() == budget - booked);
    }
  }
}
