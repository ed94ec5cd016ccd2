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
  // Two lanes (7 m); a pedestrian steps onto the road from the left 45 m
  // ahead and crosses it at 1.3 m/s, slightly against the traffic: over the
  // 7 s horizon its path covers the whole width. A car parked at the right
  // edge just before the crossing ends the ego's corridor slice first (its
  // cut lies within 2 m of the pedestrian's), so the pedestrian is not where
  // the corridor ends.
  Scene s = road_scene(1, 0);
  add_static(s, 1, 43.75, -1.4, 0, 4.5, 1.8);
  const double x_ped = 45;
  const double heading = -M_PI / 2 - 10.0 * M_PI / 180.0;
  const double y0 = 6.0;
  add_mover(s, 9, x_ped, y0, heading, 1.3, 0.8, 0.8, 12);
  const double vx = 1.3 * std::cos(heading);
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
    const double y_ped = y0 + vy * q.t;
    if (std::fabs(y_ped) < 1.75 + 0.4) {
      CHECK(front_x(s, q) < x_ped + vx * q.t - 0.4);
    }
  }
  // 12 s later the pedestrian has crossed (y = -9 m, off the road): the ego
  // goes on through the crossing.
  Scene later = s;
  later.ego.state.v = 0;
  later.ego.state.x = 30;
  Run next;
  next.go(later, 12.0);
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

TEST_CASE("traffic approaching from behind in the next lane: the ego does not move in ahead of it") {
  // The ego's lane is blocked by a parked car 45 m ahead; the only way round
  // is the left lane, where a car comes from 25 m behind at 20 m/s. Passing
  // now would put the ego in its way: it waits in its own lane.
  Scene s = road_scene(1, 0);
  s.ego.state.v = 12;
  add_static(s, 1, 45, 0.0);
  add_mover(s, 2, -25, 3.5, 0, 20);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(min_clearance(s, *r.plan) >= 0.5);
  const double half = 0.5 * s.ego.geometry.width;
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    const double car_rear = -25 + 20 * q.t - 2.25;
    if (car_rear < front_x(s, q) + 30) {  // not yet well ahead of the ego
      CHECK(q.l + half <= 1.75 + 0.1);
    }
  }
}

TEST_CASE("cut-in: the ego keeps RSS's safe distance behind the new leader, whatever its prediction says") {
  // A car 12 m ahead in the left lane at 10 m/s moves into the ego's lane
  // over 2 s and then drives on at 10 m/s (its prediction). The ego (14 m/s)
  // must end up at a gap that stays safe if the leader brakes at 8 m/s²:
  // d = v_e 0.5 + v_e²/(2 4) - v_l²/(2 8) + 2 (RssFollow, st_graph.hpp).
  Scene s = road_scene(1, 0);
  s.ego.state.v = 14;
  DynamicObstacle o;
  o.id = 21;
  o.length = 4.5;
  o.width = 1.8;
  const double x0 = 3.8 + 12 + 2.25;  // rear bumper 12 m before the ego's front
  for (int k = 0; k <= 75; ++k) {
    const double t = 0.1 * k;
    const double u = std::min(t / 2.0, 1.0);
    TimedPose p;
    p.t = t;
    p.x = x0 + 10 * t;
    p.y = 3.5 * (1 - u * u * (3 - 2 * u));
    p.heading = t < 2.0 ? -std::atan2(3.5 * 6 * u * (1 - u) / 2.0, 10.0) : 0.0;
    p.v = 10;
    (void)o.trajectory.push_back(p);
  }
  (void)s.dynamic_obstacles.push_back(o);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(decision_for(*r.plan, 21).longitudinal == itp::speed::Longitudinal::kFollow);
  // From 4 s on (lane change done, 2 s to settle) the gap is safe.
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    if (q.t < 4.0) continue;
    const double gap = (x0 + 10 * q.t - 2.25) - front_x(s, q);
    const double rss = q.v * 0.5 + q.v * q.v / 8.0 - 100.0 / 16.0 + 2.0;
    CHECK(gap >= rss - 0.5);
  }
}

TEST_CASE("braking: an ok plan brakes no harder than the situation needs; a fallback never accelerates") {
  SUBCASE("a slow leader far ahead: about 1 m/s² is enough") {
    Scene s = road_scene(0, 0);  // one lane: no passing
    s.ego.state.v = 15;
    add_mover(s, 7, 75, 0, 0, 5);
    Run r;
    r.go(s);
    REQUIRE(r.status == itp::PlanStatus::kOk);
    check_limits(s, *r.plan);
    for (const TrajectoryPoint& q : r.plan->trajectory) {
      CHECK(q.a >= -3.0 - 0.05);  // comfortable: the vehicle's limit (-6) is not needed
    }
  }
  SUBCASE("both lanes blocked: the stop only brakes") {
    Scene s = road_scene(1, 0);
    s.ego.state.v = 4;
    add_static(s, 1, 80, 0.0, 0, 4.5, 2.0);
    add_static(s, 2, 80, 3.5, 0, 4.5, 2.0);
    Run r;
    r.go(s);
    REQUIRE(r.status == itp::PlanStatus::kFallback);
    check_limits(s, *r.plan);
    for (const TrajectoryPoint& q : r.plan->trajectory) {
      if (q.v > 0.1) CHECK(q.a <= 0.05);
    }
  }
}

TEST_CASE("lateral acceleration: passing on a bend keeps v² κ within the limit at every sample") {
  // A left bend of 60 m radius, 16 m/s allowed (4.3 m/s² on the bend alone);
  // a car parked in the ego's lane is passed on the right, on the outside of
  // the bend, where the world speed is (1 - κ l) times the reference's s'.
  Scene s = road_scene(0, 1, 60, 250);
  s.road.speed_limit = 16;
  s.ego.state.v = 13;
  s.ego.state.kappa = 1.0 / 60;
  const double a = 50.0 / 60;  // parked 50 m along the bend, in the ego's lane
  add_static(s, 1, 60 * std::sin(a), 60 * (1 - std::cos(a)), a);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(min_clearance(s, *r.plan) >= 0.2);
  CHECK(decision_for(*r.plan, 1).lateral == LateralSide::kRight);
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    CHECK(std::fabs(q.v * q.v * q.kappa) <= s.ego.limits.lat_acc_max + 0.05);
  }
}

TEST_CASE("consecutive plans keep the side on which they pass a moving obstacle") {
  // A slow car in the middle of the ego's lane is passed on one side; 0.1 s
  // later it has drifted 0.3 m towards that side (CV prediction, as a noisy
  // tracker reports it). The next plan must not swing to the other side.
  Scene s = road_scene(1, 1, 0, 300);
  s.ego.state.v = 12;
  add_mover(s, 5, 40, 0.0, 0, 4);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  const LateralSide first = decision_for(*r.plan, 5).lateral;
  REQUIRE(first != LateralSide::kNone);
  const TrajectoryPoint& q = r.plan->trajectory[1];
  Scene next = s;
  next.ego.state.x = q.x;
  next.ego.state.y = q.y;
  next.ego.state.heading = q.heading;
  next.ego.state.v = q.v;
  next.ego.state.a = q.a;
  next.ego.state.kappa = q.kappa;
  next.dynamic_obstacles.clear();
  add_mover(next, 5, 40.4, first == LateralSide::kLeft ? 0.3 : -0.3, 0, 4);
  for (auto& p : next.dynamic_obstacles[0].trajectory) p.t += 0.1;
  r.go(next, 0.1);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  CHECK(decision_for(*r.plan, 5).lateral == first);
}

namespace {

// Every corner of the ego inside the road's edges (tables included), with the
// tracking tolerance of check_limits.
void check_inside_road(const Scene& s, const Plan& p) {
  const double half = 0.5 * s.ego.geometry.width;
  for (const TrajectoryPoint& q : p.trajectory) {
    CHECK(q.l + half <= s.road.left.at(q.s) + 0.2);
    CHECK(q.l - half >= s.road.right.at(q.s) - 0.2);
  }
}

void add_edge_point(Boundary& b, double s, double l) {
  BoundaryPoint p;
  p.s = s;
  p.l = l;
  REQUIRE(b.table.push_back(p));
}

}  // namespace

TEST_CASE("the road's width changes ahead: the ego plans through, the narrowing does not stop it") {
  // The convex space was cut in s only at obstacles, so on a road without
  // obstacles one slice spanned the horizon and took the narrowest road over
  // it: a lane ending or a narrowing far ahead excluded the ego's own position
  // and every path QP failed (path_qp_failed, a stop on an empty road).
  Run r;
  SUBCASE("the ego's lane ends 60-110 m ahead, the left lane is free") {
    Scene s = road_scene(1, 0, 0, 300);
    s.ego.state.v = 15;
    add_edge_point(s.road.right, 0, -1.75);
    add_edge_point(s.road.right, 60, -1.75);
    add_edge_point(s.road.right, 110, 1.75);
    s.road.target_lane_offset = 3.5;
    r.go(s);
    REQUIRE(r.status == itp::PlanStatus::kOk);
    check_inside_road(s, *r.plan);
    CHECK(r.plan->trajectory.back().v > 12.0);
    // In the left lane before the right edge reaches it.
    for (const TrajectoryPoint& q : r.plan->trajectory) {
      if (q.s > 110) CHECK(q.l > 1.75 + 0.5 * s.ego.geometry.width);
    }
  }
  SUBCASE("roadworks narrow the ego's lane by 0.8 m at its left edge 90 m ahead, the right lane is free") {
    Scene s = road_scene(0, 1, 0, 300);
    s.ego.state.v = 15;
    add_edge_point(s.road.left, 0, 1.75);
    add_edge_point(s.road.left, 90, 1.75);
    add_edge_point(s.road.left, 100, 0.95);
    r.go(s);
    REQUIRE(r.status == itp::PlanStatus::kOk);
    check_inside_road(s, *r.plan);
    CHECK(r.plan->trajectory.back().v > 12.0);
    CHECK(r.plan->trajectory[10].l == doctest::Approx(0.0).scale(1.0).epsilon(0.1));  // no jump at the start
  }
}

TEST_CASE("an oncoming car in its own lane of a narrow two-way road: no yield, no braking") {
  // Lanes of 2.76 m, the ego 2.0 m wide at 19.5 m/s in the right lane, an
  // oncoming car (1.85 m) at 20.5 m/s in the left lane: 0.83 m between them
  // when both keep their lanes. Its box (0.5 m margin) was pushed 0.2 m
  // towards the ego to fit inside the road's edges less the road margin, and
  // the ST graph tested the path with 0.3 m more on top: the path met it in
  // its own lane, and an ok plan "yielded" to it at -6 m/s².
  Scene s = road_scene(1, 0, 0, 400);
  s.road.lane_width = 2.76;
  s.road.right.offset = -1.38;
  s.road.left.offset = 1.38 + 2.76;
  s.road.speed_limit = 23.1;
  s.ego.geometry.length = 5.0;
  s.ego.geometry.width = 2.0;
  s.ego.geometry.wheelbase = 3.0;
  s.ego.state.v = 19.5;
  add_mover(s, 102, 160, 2.76, M_PI, 20.5, 4.41, 1.85);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(decision_for(*r.plan, 102).longitudinal != itp::speed::Longitudinal::kYield);
  CHECK(min_clearance(s, *r.plan) >= 0.5);
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    CHECK(q.a >= -1.0);
    CHECK(q.l + 1.0 <= 1.38 + 0.05);  // in its own lane
  }
}
