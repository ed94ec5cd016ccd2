// Scenario tests of the complete planner. Assertions are physical and checked
// independently of the planner's internals: positions, clearances from the
// real oriented boxes, accelerations, curvature and lateral acceleration
// recomputed from the trajectory samples.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "heap_guard.hpp"
#include "itp/collision/box_overlap.hpp"
#include "itp/planner/planner.hpp"
#include "itp/scene/obstacle_motion.hpp"
#include "plan_checks.hpp"
#include "scene_builder.hpp"

using namespace itp::planner;
using namespace planner_test;

using Run = PlanRun<itp::DefaultConfig>;

TEST_CASE("free road: smooth cruise up to the speed limit, in lane") {
  Scene s = road_scene(1, 0);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(r.plan->trajectory.back().v == doctest::Approx(15).epsilon(0.05));
  for (const auto& q : r.plan->trajectory) {
    CHECK(std::fabs(q.l) < 0.1);
  }
  CHECK(r.plan->iterations >= 1);
  CHECK(r.plan->iterations <= itp::DefaultConfig::kMaxPlannerIterations);
}

TEST_CASE("static obstacle in lane: passes with clearance and returns to the lane") {
  Scene s = road_scene(1, 0, 0, 250);
  add_static(s, 1, 45, 0.2);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(min_clearance(s, *r.plan) >= 0.2);
  CHECK(decision_for(*r.plan, 1).lateral == LateralSide::kLeft);
}

TEST_CASE("slow leader with no room to pass: follows at a safe gap") {
  Scene s = road_scene(0, 0);
  add_mover(s, 7, 30, 0, 0, 6);
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(min_clearance(s, *r.plan) >= 4.0);
  CHECK(decision_for(*r.plan, 7).longitudinal == itp::speed::Longitudinal::kFollow);
}

TEST_CASE("every lane blocked: fallback that stops before the obstacle within the deceleration limit") {
  Scene s = road_scene(1, 0);
  add_static(s, 1, 50, 0.0, 0, 4.5, 2.0);
  add_static(s, 2, 50, 3.5, 0, 4.5, 2.0);
  Run r;
  r.go(s);
  CHECK(r.status == itp::PlanStatus::kFallback);
  check_limits(s, *r.plan);
  CHECK(min_clearance(s, *r.plan) > 0.5);
  // At the end of the horizon the ego is slow and near enough its stop that
  // braking at 3 m/s² keeps the front bumper behind the obstacles (rear at 47.75 m).
  const TrajectoryPoint& end = r.plan->trajectory.back();
  const double front = s.ego.geometry.length - rear_overhang(s);
  CHECK(end.x + front + end.v * end.v / (2 * 3.0) <= 47.75);
  CHECK(end.v < 5.0);
}

TEST_CASE("crossing pedestrian: the ego yields") {
  // A pedestrian (0.8 m) crosses at x = 32 m from y = -5 m at 1.3 m/s: it is
  // in the ego's lane (|y| < 1.75 m, plus its half size) from 2.2 s to
  // 5.5 s, when the ego at 10 m/s would be there (its front reaches x = 32 m
  // after 2.8 s). The ego must stop short of the crossing while it is there.
  Scene s = road_scene(1, 0);
  const double x_ped = 32;
  add_mover(s, 9, x_ped, -5, M_PI / 2, 1.3, 0.8, 0.8);
  Run r;
  r.go(s);
  CHECK(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(min_clearance(s, *r.plan) >= 0.5);
  CHECK(decision_for(*r.plan, 9).longitudinal == itp::speed::Longitudinal::kYield);
  const double front = s.ego.geometry.length - rear_overhang(s);
  for (const TrajectoryPoint& q : r.plan->trajectory) {
    const double y_ped = -5 + 1.3 * q.t;
    if (std::fabs(y_ped) < 1.75 + 0.4) {
      CHECK(q.x + front < x_ped - 0.4);
    }
  }
}

TEST_CASE("curved road of 50 m radius: lateral acceleration within its limit") {
  Scene s = road_scene(1, 0, 50, 150);
  s.road.speed_limit = 20;
  s.ego.state.kappa = 1.0 / 50;
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  for (const auto& q : r.plan->trajectory) {
    CHECK(q.v * q.v / 50.0 <= s.ego.limits.lat_acc_max + 0.3);
  }
}

TEST_CASE("invalid input gives invalid_input with a safe stopping trajectory, never a crash") {
  Scene s = road_scene(1, 0);
  s.ego.state.v = std::numeric_limits<double>::quiet_NaN();
  Run r;
  r.go(s);
  CHECK(r.status == itp::PlanStatus::kInvalidInput);
  CHECK(r.plan->invalid == itp::scene::ValidationReason::kNonFiniteValue);
  REQUIRE(r.plan->trajectory.size() ==
          static_cast<std::size_t>(itp::DefaultConfig::kTrajectorySamples));
  for (const auto& q : r.plan->trajectory) {
    CHECK(std::isfinite(q.x));
    CHECK(q.v == 0);
  }
}

TEST_CASE("identical input gives bit-identical output") {
  Scene s = road_scene(1, 0);
  add_static(s, 1, 45, 0.2);
  add_mover(s, 2, 60, 3.5, M_PI, 8);
  Run a;
  Run b;
  a.go(s);
  b.go(s);
  REQUIRE(a.plan->trajectory.size() == b.plan->trajectory.size());
  CHECK(std::memcmp(a.plan->trajectory.data(), b.plan->trajectory.data(),
                    sizeof(TrajectoryPoint) * a.plan->trajectory.size()) == 0);
}

TEST_CASE("cut-in: the ego brakes within its limits and keeps clear of the merging car") {
  Scene s = road_scene(1, 0);
  s.ego.state.v = 12;
  // A car 18 m ahead in the left lane at 9 m/s merges into the ego's lane over 2.5 s.
  DynamicObstacle o;
  o.id = 21;
  o.length = 4.5;
  o.width = 1.8;
  for (int k = 0; k <= 75; ++k) {
    const double t = 0.1 * k;
    const double u = std::min(t / 2.5, 1.0);
    TimedPose p;
    p.t = t;
    p.x = 22 + 9 * t;
    p.y = 3.5 * (1 - u * u * (3 - 2 * u));  // smooth lateral move
    p.heading = t < 2.5 ? -std::atan2(3.5 * 6 * u * (1 - u) / 2.5, 9.0) : 0.0;
    p.v = 9;
    (void)o.trajectory.push_back(p);
  }
  (void)s.dynamic_obstacles.push_back(o);
  Run r;
  r.go(s);
  check_limits(s, *r.plan);
  CHECK(r.status != itp::PlanStatus::kInvalidInput);
  CHECK(min_clearance(s, *r.plan) >= 0.5);
  CHECK(r.plan->trajectory.back().v < 11.0);  // slowed down behind it
}

TEST_CASE("oncoming car beside a parked car: the ego waits or passes, never meets it") {
  Scene s = road_scene(1, 0, 0, 250);
  add_static(s, 1, 45, 0.0);                 // parked in the ego's lane
  add_mover(s, 2, 110, 3.5, M_PI, 10);       // oncoming in the other lane
  Run r;
  r.go(s);
  check_limits(s, *r.plan);
  CHECK(r.status != itp::PlanStatus::kInvalidInput);
  CHECK(min_clearance(s, *r.plan) >= 0.3);
}

// A two-lane road, a car broken down in the ego's lane at x = `breakdown`,
// and two oncoming cars 60 m apart from x = `oncoming` in the other lane.
// Planned once; the plan is ok and ends standing (the ego waits).
namespace {
void plan_waiting_behind_breakdown(Scene& s, Run& r, double breakdown, double oncoming) {
  add_static(s, 1, breakdown, 0.0);
  add_mover(s, 2, oncoming, 3.5, M_PI, 10);
  add_mover(s, 3, oncoming + 60, 3.5, M_PI, 10);
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  REQUIRE(r.plan->trajectory.back().v < 0.1);  // it waits
}
}  // namespace

TEST_CASE("waiting behind a breakdown for oncoming traffic: the ego stops where the way round still fits") {
  // Found by the independent judge (held-out seed 6: a breakdown, debris):
  // the ego waited 2 m behind a stopped car for the traffic beside it to
  // clear, and from there the turn out was beyond its steering (the path QP
  // infeasible at every curvature bound): it stood there for good.
  Scene s = road_scene(1, 0, 0, 250);
  Run r;
  plan_waiting_behind_breakdown(s, r, 40, 100);
  const auto& last = r.plan->trajectory.back();
  // To clear the car (|y| <= 0.9 m, 0.3 m margin) the ego's centre moves
  // 0.9 + 0.3 + 0.95 = 2.15 m; at the 5 m turning radius and |l'| <= 0.5 that
  // S-turn is 2 (0.5 / 0.2) + (2.15 - 0.5^2 / 0.2) / 0.5 = 6.8 m long. The
  // front bumper stops at least that far behind the car's rear (less its
  // 0.3 m margin), not 2 m.
  const double front = last.x + std::cos(last.heading) * itp::scene::front_reach(s.ego.geometry);
  CHECK(40 - 2.25 - 0.3 - front >= 6.8 - 0.05);
}

TEST_CASE("waiting behind a breakdown from across the lane line: the ego stops back in its lane") {
  // The default suite's seed 6 (paper-0161): a path still coming back from a
  // swerve, with the stop moved back by the turn's length, left the ego
  // standing half in the oncoming lane (7 cm from the oncoming car). The
  // stop room applies only from within the lane.
  Scene s = road_scene(1, 0, 0, 250);
  s.ego.state.y = 1.5;
  s.ego.state.v = 5;
  Run r;
  plan_waiting_behind_breakdown(s, r, 16, 80);
  const auto& last = r.plan->trajectory.back();
  // Its body within its lane (stopped 1.6 m further back, it stood at l = 0.90).
  CHECK(std::fabs(last.l) <= 0.5 * (3.5 - 1.9) + 0.05);
}

TEST_CASE("straddling two lanes beside a faster car from behind: an ok plan, not a stop on the path budget") {
  // Found by the independent judge (seed 6, slow_leader): the ego half in the
  // left lane, behind a slow leader, while a faster car comes up in that
  // lane. The car's SL box covers the ego's own s, so the corridor starts
  // beside the ego; with the start admitted only within the first block
  // every path QP was infeasible and every cycle fell back (budget) until
  // the ego stood still.
  Scene s = road_scene(1, 0, 0, 250);
  s.ego.state.y = 1.6;
  s.ego.state.v = 3.1;
  add_mover(s, 1, 16, 0.0, 0, 2.8);    // the slow leader in the ego's lane
  add_mover(s, 2, -4, 3.5, 0, 5.5);    // faster, in the left lane, beside and behind
  Run r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  // The start is 5 cm from the passing car's side: never closer, and back
  // in its own lane (|l| < 0.5 m) 4 s on.
  CHECK(min_clearance(s, *r.plan) >= 0.03);
  for (const auto& q : r.plan->trajectory) {
    if (q.t >= 4.0) CHECK(std::fabs(q.l) < 0.5);
  }
}

TEST_CASE("after reset() a reused planner gives bit-identical output to a fresh one") {
  Scene a = road_scene(1, 0);
  add_static(a, 1, 45, 0.2);
  Scene b = road_scene(1, 0);
  add_mover(b, 2, 40, 0, 0, 6);
  add_static(b, 3, 70, 3.5);
  Run reused;
  reused.go(a);
  reused.go(b, 0.1);
  reused.planner->reset();
  reused.go(b);
  Run fresh;
  fresh.go(b);
  REQUIRE(reused.plan->trajectory.size() == fresh.plan->trajectory.size());
  CHECK(reused.plan->qp_iterations == fresh.plan->qp_iterations);
  CHECK(std::memcmp(reused.plan->trajectory.data(), fresh.plan->trajectory.data(),
                    sizeof(TrajectoryPoint) * fresh.plan->trajectory.size()) == 0);
}

TEST_CASE("a reference line that starts later (a sender's window) keeps stitching to the previous plan") {
  // Cycle 1 plans a pass; cycle 2, 0.1 s later with the ego where the plan put
  // it, gets the same road either whole or without its first 3 points (s = 0
  // moves 6 m). Both must stitch to cycle 1's plan and plan the same motion.
  Scene s = road_scene(1, 0, 0, 250);
  add_static(s, 1, 45, 0.2);
  Run first;
  first.go(s);
  REQUIRE(first.status == itp::PlanStatus::kOk);
  const TrajectoryPoint& q = first.plan->trajectory[1];
  Scene next = s;
  next.ego.state.x = q.x;
  next.ego.state.y = q.y;
  next.ego.state.heading = q.heading;
  next.ego.state.v = q.v;
  next.ego.state.a = q.a;
  next.ego.state.kappa = q.kappa;
  Scene cropped = next;
  cropped.reference_line.clear();
  for (std::size_t i = 3; i < next.reference_line.size(); ++i) {
    REQUIRE(cropped.reference_line.push_back(next.reference_line[i]));
  }
  Run whole = std::move(first);
  Run shifted;
  shifted.go(s);
  whole.go(next, 0.1);
  shifted.go(cropped, 0.1);
  REQUIRE(whole.status == itp::PlanStatus::kOk);
  REQUIRE(shifted.status == itp::PlanStatus::kOk);
  CHECK(shifted.plan->iterations == whole.plan->iterations);
  REQUIRE(shifted.plan->trajectory.size() == whole.plan->trajectory.size());
  for (std::size_t k = 0; k < whole.plan->trajectory.size(); ++k) {
    const TrajectoryPoint& a = whole.plan->trajectory[k];
    const TrajectoryPoint& b = shifted.plan->trajectory[k];
    CHECK(std::hypot(a.x - b.x, a.y - b.y) < 0.01);
    CHECK(b.s == doctest::Approx(a.s - 6.0).epsilon(1e-3));
  }
}
