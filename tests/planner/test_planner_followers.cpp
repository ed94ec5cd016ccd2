// Traffic coming up from behind (issue 11, "Stopped in the way of traffic"):
// recorded traffic does not react to the ego, so an ego that brakes for a
// phantom, yields to a car behind it or swerves away from a merging car gets
// hit. RSS (Shalev-Shwartz et al. 2017): the car behind keeps its distance;
// the ego keeps its lane and brakes no harder than what lies ahead needs.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "itp/planner/planner.hpp"
#include "plan_checks.hpp"
#include "scene_builder.hpp"

using namespace itp::planner;
using namespace planner_test;

using Run = PlanRun<itp::DefaultConfig>;

TEST_CASE("a car from behind merges into the ego's lane behind it: the ego keeps its lane and speed") {
  // As in CommonRoad ZAM_Tutorial-1_1: the ego at 22 m/s in its lane, a car
  // 12 m behind in the left lane at 23 m/s (the speed limit) heading 3 deg
  // towards the ego's lane (constant velocity: a lane change that ends in
  // the ego's lane, behind the ego). It becomes a follower there: its sweep
  // must not close the ego's own lane (it did: path QP failure, fallback).
  Scene s = road_scene(1, 0, 0, 400);
  s.road.speed_limit = 23;
  s.ego.state.v = 22;
  add_mover(s, 42, -12, 3.5, -0.05, 23);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    CHECK(std::fabs(q.l) < 0.3);  // its own lane
    CHECK(q.a >= -1.0);           // no braking for the car behind
  }
  CHECK(decision_for(*r.plan, 42).longitudinal != itp::speed::Longitudinal::kYield);
}

TEST_CASE("a faster follower in the ego's lane while the ego slows for a leader: an ok plan, braking gently") {
  // One lane. A slow car 60 m ahead (5 m/s) needs about 1 m/s^2; a car 9 m
  // behind keeps 15 m/s in its (constant-velocity) prediction and so runs
  // into any ego that slows down. The gap is the follower's to keep (RSS):
  // the plan follows the leader as it would without the follower, instead of
  // a collision fallback that brakes at 3 m/s^2 (and gets hit sooner).
  Scene s = road_scene(0, 0);
  s.ego.state.v = 15;
  add_mover(s, 7, 60, 0, 0, 5);
  add_mover(s, 8, -9, 0, 0, 15);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(decision_for(*r.plan, 7).longitudinal == itp::speed::Longitudinal::kFollow);
  CHECK(decision_for(*r.plan, 8).longitudinal == itp::speed::Longitudinal::kIgnore);
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    CHECK(q.a >= -3.0 - 0.05);
  }
}

TEST_CASE("a follower closing in on a slow ego: the ego does not yield to it") {
  // The ego at 4 m/s, a car 2.3 m behind its rear bumper at 9 m/s in the
  // same lane. The ego cannot stay ahead of it (it would have to be faster
  // than 9 m/s at once), and yielding to it (staying behind where its
  // constant-velocity prediction drives through the ego) meant braking hard
  // in front of it.
  Scene s = road_scene(0, 0);
  s.ego.state.v = 4;
  add_mover(s, 8, -5.5, 0, 0, 9);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(decision_for(*r.plan, 8).longitudinal == itp::speed::Longitudinal::kIgnore);
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    CHECK(q.v >= 4.0 - 0.2);  // never slower than now
  }
}

TEST_CASE("a follower whose recorded speeds say 0: its speed is read from its motion") {
  // As the recorded queue car in USA_Peach-4_8 (ground-truth predictions):
  // the trajectory's poses advance at 15 m/s while its speed fields are 0.
  // The rear-end rule compared the ego's speed with the field and counted
  // the hit as the ego's: a collision fallback instead of following the leader.
  Scene s = road_scene(0, 0);
  s.ego.state.v = 15;
  add_mover(s, 7, 60, 0, 0, 5);
  add_mover(s, 8, -9, 0, 0, 15);
  for (TimedPose& p : s.dynamic_obstacles[1].trajectory) p.v = 0;
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(decision_for(*r.plan, 7).longitudinal == itp::speed::Longitudinal::kFollow);
}

TEST_CASE("a faster car behind in the ego's lane is not a lateral obstacle: the ego does not swerve") {
  // Two lanes; the ego at 18 m/s, a car 10 m behind it in its lane at 23
  // m/s (the speed limit). It catches up with the ego within the horizon; as
  // a box in the convex space where it meets the ego, it made the plan pass
  // it on the left - out of the ego's lane in front of it.
  Scene s = road_scene(1, 0, 0, 400);
  s.road.speed_limit = 23;
  s.ego.state.v = 18;
  add_mover(s, 42, -10, 0, 0, 23);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(decision_for(*r.plan, 42).lateral == LateralSide::kNone);
  CHECK(decision_for(*r.plan, 42).longitudinal == itp::speed::Longitudinal::kIgnore);
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    CHECK(std::fabs(q.l) < 0.3);
  }
}

TEST_CASE("the map ends ahead and a car follows closely: the ego brakes late, comfortably") {
  // As ZAM_Tutorial-1_1 near its end: the road ends 130 m ahead of the ego
  // (20 m/s), so the plan stops before it; a car 9 m behind keeps 21 m/s.
  // Without it the speed QP spreads the stop over the horizon and slows down
  // from the first second; with it the ego keeps its speed while braking at
  // comfort_decel (3 m/s^2) later still stops before the end.
  Scene s = road_scene(0, 0, 0, 130);
  s.road.speed_limit = 23;
  s.ego.state.v = 20;
  add_mover(s, 42, -9, 0, 0, 21);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    if (q.t <= 1.5) CHECK(q.v >= 20.0 - 1e-3);  // no early braking (main: 19.8 m/s at 1.5 s)
    CHECK(q.a >= -3.0 - 0.3);
    CHECK(q.x + s.ego.geometry.length - rear_overhang(s) <= 130.0);
  }
}

TEST_CASE("the map ends within the horizon and a faster car follows: ok plans that keep the speed, within the speed budget") {
  // As ZAM_Tutorial-1_1 from 1.1 s on: the ego at 22.5 m/s and accelerating
  // gently, the road ending 165 m ahead, a car 9 m behind at 23 m/s (the
  // speed limit). Keeping ahead of it asked for the furthest reachable motion
  // (a_max) less 0.2 m while the stop's speed bound fell faster than
  // comfortable braking: every speed QP with it was infeasible, each
  // certified after about 70 iterations, and the cycles ran out of their
  // speed budget (`budget` fallbacks, braking in front of the follower: main
  // was rear-ended there). Braking at comfort_decel (3 m/s^2) from 22.7 m/s
  // takes 86 m + 6.8 m of onset: the ego can hold its speed for 2.5 s.
  // Closed loop, 3 s: the ego follows each plan for 0.1 s.
  Scene s = road_scene(0, 0, 0, 165);
  s.road.speed_limit = 23;
  s.ego.state.v = 22.5;
  s.ego.state.a = 0.5;
  add_mover(s, 42, -9, 0, 0, 23);
  Run r;
  for (int cycle = 0; cycle <= 30; ++cycle) {
    const double now = 0.1 * cycle;
    Scene here = s;
    here.dynamic_obstacles.clear();
    add_mover(here, 42, -9 + 23 * now, 0, 0, 23);
    for (auto& p : here.dynamic_obstacles[0].trajectory) p.t += now;
    r.go(here, now);
    REQUIRE_MESSAGE(r.status == itp::PlanStatus::kOk, "cycle ", cycle, ": ", std::string(itp::planner::to_string(r.plan->fallback)));
    check_limits(here, *r.plan);
    CHECK(r.plan->timing.speed_iterations < itp::DefaultConfig::kMaxSpeedIterationsPerCycle);
    for (const TrajectoryPoint& q : r.plan->trajectory) {
      CHECK(q.x + s.ego.geometry.length - rear_overhang(s) <= 165.0);
    }
    const TrajectoryPoint& q = r.plan->trajectory[1];
    CHECK(q.a >= -3.0 - 0.3);  // what the ego drives: comfortable
    if (now <= 2.0) CHECK_MESSAGE(q.v >= 22.5 - 0.3, "cycle ", cycle);  // no early braking
    s.ego.state.x = q.x;
    s.ego.state.v = q.v;
    s.ego.state.a = q.a;
  }
}
