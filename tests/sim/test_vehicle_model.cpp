// Kinematic bicycle and tracking controller.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "sim/vehicle_model.hpp"

using namespace hil::sim;

namespace {
// A plan along a circle of signed radius (left turn positive) or a straight line (radius 0).
std::vector<TrajectoryPoint> circle_plan(double radius, double v, double t_end, double y0 = 0.0) {
  std::vector<TrajectoryPoint> plan;
  for (int k = 0; k * 0.1 <= t_end + 1e-9; ++k) {
    const double t = k * 0.1;
    const double s = v * t;
    TrajectoryPoint p;
    p.t = t;
    p.v = v;
    if (radius == 0.0) {
      p.x = s;
      p.y = y0;
    } else {
      const double phi = s / radius;
      p.x = radius * std::sin(phi);
      p.y = radius - radius * std::cos(phi);
      p.heading = std::remainder(phi, 2.0 * std::numbers::pi);
      p.kappa = 1.0 / radius;
    }
    plan.push_back(p);
  }
  return plan;
}
}  // namespace

TEST_CASE("bicycle: constant steering draws a circle of radius L / tan(delta) within 1 %") {
  for (double delta : {0.05, 0.3, -0.5}) {
    VehicleParams p;
    p.max_steer_rate = 0.0;  // immediate
    VehicleState s;
    s.v = 6.0;
    s.steer = delta;
    const double radius = p.wheelbase / std::tan(delta);  // signed
    const double cx = 0.0, cy = radius;                  // centre left of +x for delta > 0
    const double period = 2.0 * std::numbers::pi * std::abs(radius) / s.v;
    double worst = 0.0;
    for (int k = 0; k < 200; ++k) {
      step_vehicle(s, p, VehicleCommand{0.0, delta}, period / 200.0);
      worst = std::max(worst, std::abs(std::hypot(s.x - cx, s.y - cy) - std::abs(radius)));
    }
    CHECK(worst < 0.01 * std::abs(radius));
    CHECK(std::hypot(s.x, s.y) < 0.01 * std::abs(radius));  // back at the start after one lap
  }
}

TEST_CASE("bicycle: acceleration limits, no reversing, steer rate limit") {
  VehicleParams p;
  VehicleState s;
  s.v = 2.0;
  step_vehicle(s, p, VehicleCommand{-20.0, 0.0}, 1.0);  // clamps to -8, stops at 0
  CHECK(s.v == 0.0);
  CHECK(s.x == doctest::Approx(2.0 * 2.0 / (2.0 * 8.0)).epsilon(1e-6));
  step_vehicle(s, p, VehicleCommand{10.0, 0.6}, 0.5);
  CHECK(s.v == doctest::Approx(1.5));   // max_accel 3
  CHECK(s.steer == doctest::Approx(0.4));  // 0.8 rad/s for 0.5 s
}

TEST_CASE("controller: tracks a straight plan from a 1 m offset to < 0.2 m") {
  TrackingController c;
  VehicleState s;
  s.v = 10.0;
  c.set_plan(circle_plan(0.0, 10.0, 30.0, 1.0), 0.0);
  for (int k = 0; k < 100; ++k) c.advance(s, k * 0.1, 0.1);  // 10 s
  CHECK(std::abs(s.y - 1.0) < 0.2);
  CHECK(std::abs(c.last_errors().lateral) < 0.2);
  CHECK(std::abs(s.v - 10.0) < 0.1);
  MESSAGE("straight: final lateral error " << s.y - 1.0 << " m");
}

TEST_CASE("controller: tracks circular plans (left and right, R = 40..200 m) to < 0.2 m") {
  for (double radius : {40.0, 80.0, -200.0}) {
    TrackingController c;
    VehicleState s;
    s.y = -0.5;  // start 0.5 m to the right
    s.v = 8.0;   // and 2 m/s slow
    c.set_plan(circle_plan(radius, 10.0, 40.0), 0.0);
    double worst_late = 0.0;
    for (int k = 0; k < 300; ++k) {
      c.advance(s, k * 0.1, 0.1);
      const double e = std::abs(std::hypot(s.x, s.y - radius) - std::abs(radius));
      if (k >= 100) worst_late = std::max(worst_late, e);  // steady state: after 10 s
    }
    CAPTURE(radius);
    CHECK(worst_late < 0.2);
    CHECK(std::abs(s.v - 10.0) < 0.1);
    MESSAGE("R = " << radius << ": steady-state radial error <= " << worst_late << " m");
  }
}

TEST_CASE("controller: emergency brake decelerates at the given rate and holds steering") {
  TrackingController c;
  VehicleState s;
  s.v = 10.0;
  s.steer = 0.05;
  c.set_plan(circle_plan(0.0, 10.0, 7.0), 0.0);
  c.emergency_brake(4.0);
  CHECK(c.braking());
  c.advance(s, 0.0, 1.0);
  CHECK(s.v == doctest::Approx(6.0).epsilon(1e-9));
  CHECK(s.steer == doctest::Approx(0.05));
  c.advance(s, 1.0, 3.0);
  CHECK(s.v == 0.0);
  c.set_plan(circle_plan(0.0, 10.0, 7.0), 4.0);
  CHECK_FALSE(c.braking());
}

TEST_CASE("sample_plan interpolates in time and clamps at the ends") {
  const auto plan = circle_plan(0.0, 10.0, 7.0);
  CHECK(sample_plan(plan, 0.25).x == doctest::Approx(2.5));
  CHECK(sample_plan(plan, 99.0).x == doctest::Approx(70.0));
  CHECK(sample_plan(plan, -1.0).x == doctest::Approx(0.0));
}
