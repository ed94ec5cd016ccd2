// Dynamic obstacle pose at time t: appears-later, interpolation and
// moving on after the last sample (scene/1 semantics).
#include <doctest/doctest.h>

#include <cmath>

#include "itp/scene/obstacle_motion.hpp"

using itp::Scalar;
using itp::scene::DynamicObstacle;
using itp::scene::sample_pose;

namespace {
DynamicObstacle make() {
  DynamicObstacle d;
  d.id = 3;
  d.length = Scalar(4.5);
  d.width = Scalar(1.8);
  // Appears at t = 1 s; uneven steps; turns from +170 deg to -170 deg.
  (void)d.trajectory.push_back({Scalar(1.0), Scalar(0), Scalar(0), Scalar(2.9670597), Scalar(4)});
  (void)d.trajectory.push_back({Scalar(1.5), Scalar(-2), Scalar(0.2), Scalar(-2.9670597), Scalar(6)});
  (void)d.trajectory.push_back({Scalar(2.5), Scalar(-8), Scalar(1.0), Scalar(3.14159265), Scalar(6)});
  return d;
}
}  // namespace

TEST_CASE("An obstacle whose first sample is later than 0 is absent before it") {
  const DynamicObstacle d = make();
  CHECK_FALSE(sample_pose(d, Scalar(0)).present);
  CHECK_FALSE(sample_pose(d, Scalar(0.999)).present);
  const auto p = sample_pose(d, Scalar(1.0));
  CHECK(p.present);
  CHECK(p.x == Scalar(0));
  CHECK(p.v == Scalar(4));
}

TEST_CASE("Between samples the pose is interpolated, heading across +-pi the short way") {
  const DynamicObstacle d = make();
  const auto p = sample_pose(d, Scalar(1.25));
  CHECK(p.present);
  CHECK(static_cast<double>(p.x) == doctest::Approx(-1.0));
  CHECK(static_cast<double>(p.y) == doctest::Approx(0.1));
  CHECK(static_cast<double>(p.v) == doctest::Approx(5.0));
  // Midway between +170 and -170 deg is 180 deg, not 0.
  CHECK(std::fabs(static_cast<double>(p.heading)) == doctest::Approx(3.14159265).epsilon(1e-6));
  const auto q = sample_pose(d, Scalar(2.0));
  CHECK(static_cast<double>(q.x) == doctest::Approx(-5.0));
  CHECK(static_cast<double>(q.y) == doctest::Approx(0.6));
}

TEST_CASE("After the last sample the obstacle moves on at its last velocity and heading") {
  const DynamicObstacle d = make();
  const auto p = sample_pose(d, Scalar(4.5));  // 2 s after the last sample
  CHECK(p.present);
  CHECK(static_cast<double>(p.x) == doctest::Approx(-8.0 - 12.0).epsilon(1e-6));
  CHECK(static_cast<double>(p.y) == doctest::Approx(1.0).epsilon(1e-6));
  CHECK(static_cast<double>(p.v) == doctest::Approx(6.0));
}
