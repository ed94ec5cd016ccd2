// Behaviour found by independent testing (issue 11, "Behaviour"): each case is
// a situation that made the planner stop, collide or misreport, with physical
// assertions on the returned plan.
#include <doctest/doctest.h>

#include <cmath>

#include "itp/planner/planner.hpp"
#include "plan_checks.hpp"
#include "scene_builder.hpp"

using namespace itp::planner;
using namespace planner_test;

using Run = PlanRun<itp::DefaultConfig>;

namespace {

// Front bumper's path s (x on the straight test roads) at a trajectory sample.
double front_x(const Scene& s, const TrajectoryPoint& q) {
  return q.x + s.ego.geometry.length - rear_overhang(s);
}

}  // namespace

TEST_CASE("crossing pedestrian whose sweep covers the road: an ok plan that yields, then goes on") {
  // Two lanes (7 m); a pedestrian steps onto the road 45 m ahead and crosses
  // it at 1.3 m/s, slightly against the traffic (100 deg): over the 7 s
  // horizon its path covers the whole width. A car parked 4 m before the
  // crossing narrows the ego's lane (the corridor then ends at the parked
  // car, not at the pedestrian).
  Scene s = road_scene(1, 0);
  add_static(s, 1, 41, -1.4, 0, 4.5, 1.8);
  const double x_ped = 45;
  const double heading = M_PI / 2 + 10.0 * M_PI / 180.0;
  add_mover(s, 9, x_ped, -2.5, heading, 1.3, 0.8, 0.8, 12);
  const double vy = 1.3 * std::sin(heading);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(decision_for(*r.plan, 9).longitudinal == itp::speed::Longitudinal::kYield);
  CHECK(min_clearance(s, *r.plan) >= 0.5);
  // While any part of the pedestrian (0.8 m) is in the ego's lane (|y| <
  // 1.75 m), the ego's front stays before the crossing.
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    const double y_ped = -2.5 + vy * q.t;
    const double x_now = x_ped + 1.3 * std::cos(heading) * q.t;
    if (std::fabs(y_ped) < 1.75 + 0.4) {
      CHECK(front_x(s, q) < x_now - 0.4);
    }
  }
  // 9 s later the pedestrian has crossed (y = 9 m, off the road): the ego
  // goes on through the crossing.
  Scene later = s;
  later.ego.state.v = 0;
  later.ego.state.x = 30;
  Run next;
  next.go(later, 9.0);
  REQUIRE(next.status == itp::PlanStatus::kOk);
  check_limits(later, *next.plan);
  CHECK(front_x(later, next.plan->trajectory.back()) > x_ped + 5);
}

TEST_CASE("the map ends ahead: an ok plan that stops before the end") {
  // The reference line (the road) ends 60 m ahead of a car at 10 m/s.
  Scene s = road_scene(1, 0, 0, 60);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  const TrajectoryPoint& end = r.plan->trajectory.back();
  CHECK(end.v < 0.05);
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    CHECK(front_x(s, q) <= 60.0);
  }
  SUBCASE("only 12 m of road left, and the car stands near its end") {
    Scene near = road_scene(1, 0, 0, 12);
    near.ego.state.v = 0;
    near.ego.state.x = 2;
    Run n;
    n.go(near);
    REQUIRE(n.status == itp::PlanStatus::kOk);
    check_limits(near, *n.plan);
    for (const TrajectoryPoint& q : n.plan->trajectory) {
      CHECK(front_x(near, q) <= 12.0);
    }
  }
}

TEST_CASE("fast driving: the path covers where the speed plan goes, obstacles beyond 100 m included") {
  // At 19 m/s the 7 s speed horizon reaches 133 m; a car stands in the ego's
  // lane 120 m ahead, beyond the paper's 100 m path. The plan must pass it or
  // stop for it, not run into it at the end of the horizon.
  Scene s = road_scene(1, 0, 0, 400);
  s.road.speed_limit = 20;
  s.ego.state.v = 19;
  add_static(s, 1, 120, 0.0);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(min_clearance(s, *r.plan) >= 0.2);
}
