// Keeping ahead of a follower (speed/keep_ahead.hpp): the lower bounds are
// never ahead of a motion the ego can drive (holding its speed, then the
// latest braking that keeps every bound), checked against the kinematics
// worked out by hand.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "itp/speed/keep_ahead.hpp"

using namespace itp::speed;
using itp::Scalar;
using Cfg = itp::DefaultConfig;

namespace {

constexpr double kDt = 7.0 / Cfg::kSpeedSamples;  // [s]
constexpr Scalar kNoLimit = std::numeric_limits<Scalar>::infinity();

SpeedBounds bounds(double s_hi, double v_hi) {
  SpeedBounds b;
  for (int k = 0; k < Cfg::kStSamples; ++k) {
    b.s_hi[static_cast<std::size_t>(k)] = s_hi;
    b.v_hi[static_cast<std::size_t>(k)] = v_hi;
  }
  return b;
}

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
  SpeedBounds b = bounds(100, 30);
  const double t_switch = (100.0 - (20.0 * 0.5 - 3.0 * 0.25 / 6.0 + 19.25 * 19.25 / 6.0)) / 20.0;
  REQUIRE(t_switch == doctest::Approx(1.418).epsilon(1e-3));
  const int m = latest_braking(p, b, Scalar(-3), kNoLimit, Scalar(0.005));
  CHECK(m == 14);
  std::array<Scalar, Cfg::kStSamples> s{};
  braking_motion(p, m, Scalar(-3), s);
  for (int k = 0; k < Cfg::kStSamples; ++k) {
    const double t = kDt * k;
    const double sk = s[static_cast<std::size_t>(k)];
    CHECK(sk <= 100.0 + 0.005);
    if (t <= 1.4 + 1e-9) CHECK(sk == doctest::Approx(20.0 * t));  // still holding
    if (t >= 1.5 - 1e-9) CHECK(sk < 20.0 * t - 1e-3);             // braking
  }
  CHECK(s.back() == doctest::Approx(28.0 + 9.875 + 19.25 * 5.1 - 1.5 * 5.1 * 5.1).epsilon(1e-3));
  // Further off (200 m): holding to the horizon's end (140 m), braking after it (71.64 m).
  b = bounds(220, 30);
  CHECK(latest_braking(p, b, Scalar(-3), kNoLimit, Scalar(0.005)) == Cfg::kStSamples - 1);
  b = bounds(205, 30);
  CHECK(latest_braking(p, b, Scalar(-3), kNoLimit, Scalar(0.005)) < Cfg::kStSamples - 1);
  // A bound that braking from now cannot meet: none.
  b = bounds(60, 30);
  CHECK(latest_braking(p, b, Scalar(-3), kNoLimit, Scalar(0.005)) == -1);
  // Bounds at or beyond s_limit (the end of the planned path) are no stop.
  CHECK(latest_braking(p, b, Scalar(-3), Scalar(60), Scalar(0.005)) == Cfg::kStSamples - 1);
}

TEST_CASE("latest braking: a speed bound that falls is met in time") {
  // v_hi drops from 30 to 5 m/s at 6 s. From 20 m/s the ramp leaves 19.25
  // m/s after 0.5 s and 3 m/s^2 takes 4.75 s more to 5 m/s: 5.25 s in all,
  // so braking starts by 0.75 s: the latest sample 0.7 s.
  StParams p;
  p.v0 = 20;
  SpeedBounds b = bounds(1000, 30);
  for (int k = 0; k < Cfg::kStSamples; ++k) {
    if (kDt * k >= 6.0 - 1e-9) b.v_hi[static_cast<std::size_t>(k)] = 5;
  }
  const int m = latest_braking(p, b, Scalar(-3), kNoLimit, Scalar(0.005));
  CHECK(m == 7);
  std::array<Scalar, Cfg::kStSamples> s{};
  braking_motion(p, m, Scalar(-3), s);
  // Its speed from the distances: at most 5 m/s from 6 s on.
  for (int k = 61; k < Cfg::kStSamples; ++k) {
    CHECK((s[static_cast<std::size_t>(k)] - s[static_cast<std::size_t>(k - 1)]) / kDt <= 5.0 + 0.01);
  }
}
