// Keeping ahead of a follower (speed/keep_ahead.hpp): the lower bounds are
// never ahead of a motion the ego can drive (holding its speed, then the
// latest braking that keeps every upper bound), checked against the
// kinematics worked out by hand.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "itp/speed/keep_ahead.hpp"

using namespace itp::speed;
using itp::Scalar;
using Cfg = itp::DefaultConfig;

namespace {

constexpr double kDt = 7.0 / Cfg::kSpeedSamples;  // [s]

}  // namespace

TEST_CASE("latest braking: hold the speed, then brake at the last sample that still stops before the bound") {
  // 20 m/s, a stop 100 m ahead, braking at 3 m/s^2 after the acceleration
  // ramps from 0 to -3 over 0.5 s. By hand: the ramp covers 20 * 0.5 - 3 *
  // 0.5^2 / 6 = 9.875 m and leaves 19.25 m/s; braking then takes 19.25^2 / 6
  // = 61.76 m: 71.64 m in all, so the braking must start by (100 - 71.64) /
  // 20 = 1.418 s: the latest sample 1.4 s. The stop takes 6.92 s, beyond the
  // 7 s horizon: at 7 s the ego is at 28 + 9.875 + 19.25 * 5.1 - 1.5 * 5.1^2
  // = 97.03 m, and still stops before 100 m after it.
  StParams p;
  p.v0 = 20;
  p.a0 = 0;
  SpeedBounds b;
  for (int k = 0; k < Cfg::kStSamples; ++k) {
    b.s_hi[static_cast<std::size_t>(k)] = 100;
    b.v_hi[static_cast<std::size_t>(k)] = 30;
  }
  BasicEgoProfile<Cfg> hold;
  holding(p, b, Scalar(-3), hold);
  for (int k = 0; k < Cfg::kStSamples; ++k) {
    CHECK(hold.s[static_cast<std::size_t>(k)] == doctest::Approx(20.0 * kDt * k));
  }
  std::array<Scalar, Cfg::kStSamples> late{};
  REQUIRE(latest_braking(b, hold, Scalar(-3), std::numeric_limits<Scalar>::infinity(), Scalar(0.005), late));
  const double t_switch = (100.0 - (20.0 * 0.5 - 3.0 * 0.25 / 6.0 + 19.25 * 19.25 / 6.0)) / 20.0;
  REQUIRE(t_switch == doctest::Approx(1.418).epsilon(1e-3));
  for (int k = 0; k < Cfg::kStSamples; ++k) {
    const double t = kDt * k;
    const double s = late[static_cast<std::size_t>(k)];
    CHECK(s <= 100.0 + 0.005);
    if (t <= 1.4 + 1e-9) CHECK(s == doctest::Approx(20.0 * t));  // still holding
    if (t >= 1.5 - 1e-9) CHECK(s < 20.0 * t);                     // braking
  }
  CHECK(late.back() == doctest::Approx(28.0 + 9.875 + 19.25 * 5.1 - 1.5 * 5.1 * 5.1).epsilon(1e-3));
  // A bound that braking from now cannot meet: none.
  for (auto& s : b.s_hi) s = 60;
  CHECK_FALSE(latest_braking(b, hold, Scalar(-3), std::numeric_limits<Scalar>::infinity(), Scalar(0.005), late));
  // Bounds at or beyond s_limit (the end of the planned path) are no stop.
  CHECK(latest_braking(b, hold, Scalar(-3), Scalar(60), Scalar(0.005), late));
  CHECK(late.back() == doctest::Approx(20.0 * 7.0));
}

TEST_CASE("holding: a speed bound that falls faster than braking is met by braking earlier") {
  // v_hi drops from 30 to 5 m/s at 6 s. At 3 m/s^2 the ego gets from 20 to
  // 5 m/s in 5 s: it holds 20 m/s up to 1 s, then follows 5 + 3 (6 - t).
  StParams p;
  p.v0 = 20;
  SpeedBounds b;
  for (int k = 0; k < Cfg::kStSamples; ++k) {
    b.s_hi[static_cast<std::size_t>(k)] = 1000;
    b.v_hi[static_cast<std::size_t>(k)] = kDt * k < 6.0 - 1e-9 ? 30 : 5;
  }
  BasicEgoProfile<Cfg> hold;
  holding(p, b, Scalar(-3), hold);
  for (int k = 1; k < Cfg::kStSamples; ++k) {
    const auto u = static_cast<std::size_t>(k);
    const double t = kDt * k;
    const double expected = std::min(20.0, t < 6.0 - 1e-9 ? 5.0 + 3.0 * (6.0 - t) : 5.0);
    CHECK(hold.v[u] == doctest::Approx(expected));
    CHECK(hold.v[u] >= hold.v[u - 1] - 3.0 * kDt - 1e-9);  // never braking harder than 3 m/s^2
  }
}
