// Issue 13, the planner's share of defects 1, 2 and 11: the planner called
// directly (inproc, planner_cli) checks the scene time, stops an invalid
// scene from the last valid state, and answers a repeated request with the
// same plan. (The firmware service's share: tests/app/test_service_link.cpp.)
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "itp/planner/planner.hpp"
#include "scene_builder.hpp"

using planner_test::add_mover;
using planner_test::add_static;
using planner_test::road_scene;

TEST_CASE("planner: a scene time that is NaN, infinite or negative is invalid_input") {
  auto planner = std::make_unique<itp::planner::Planner>();
  auto plan = std::make_unique<itp::planner::Plan>();
  auto scene = std::make_unique<itp::scene::Scene>(road_scene(1, 0));
  for (const double now : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), -1.0}) {
    planner->reset();
    planner->plan({scene.get(), now}, *plan);
    CHECK(plan->status == itp::PlanStatus::kInvalidInput);
    CHECK(plan->invalid == itp::scene::ValidationReason::kSceneTimeOutOfRange);
  }
}

// The stop starts from the previous ok plan at `now` (about 10 m/s), never
// from the rejected ego state.
TEST_CASE("planner: the stop of an invalid scene never runs at the rejected ego speed") {
  auto planner = std::make_unique<itp::planner::Planner>();
  auto plan = std::make_unique<itp::planner::Plan>();
  auto scene = std::make_unique<itp::scene::Scene>(road_scene(1, 0));
  planner->plan({scene.get(), 0.0}, *plan);
  REQUIRE(plan->status == itp::PlanStatus::kOk);
  const double v_now = plan->trajectory[1].v;  // the plan's speed at t = 0.1 s
  REQUIRE(v_now < 11.0);
  scene->ego.state.v = 1e9;  // rejected: above 70 m/s
  planner->plan({scene.get(), 0.1}, *plan);
  REQUIRE(plan->status == itp::PlanStatus::kInvalidInput);
  for (const auto& p : plan->trajectory) {
    CHECK(p.v <= v_now + 1e-9);  // at most the last valid speed, braking from there
    CHECK(std::fabs(p.x) < 1e3);
  }
}

// Defect 11: the same scene sent twice (no reset) gives the same plan; before,
// the second call stitched onto the first call's plan at age 0 and the
// decision hysteresis flipped, so calls alternated between two plans.
TEST_CASE("planner: the same scene twice gives the same plan") {
  auto planner = std::make_unique<itp::planner::Planner>();
  auto first = std::make_unique<itp::planner::Plan>();
  auto second = std::make_unique<itp::planner::Plan>();
  auto scene = std::make_unique<itp::scene::Scene>(road_scene(1, 0));
  add_static(*scene, 1, 45, 0.3);
  add_mover(*scene, 2, 80, 3.5, 3.14159, 8);
  planner->plan({scene.get(), 0.0}, *first);
  int differing = 0;
  for (int k = 0; k < 4; ++k) {
    planner->plan({scene.get(), 0.0}, *second);
    differing += first->trajectory.size() == second->trajectory.size() &&
                         std::memcmp(first->trajectory.data(), second->trajectory.data(),
                                     first->trajectory.size() * sizeof(itp::planner::TrajectoryPoint)) == 0
                     ? 0
                     : 1;
  }
  CHECK(differing == 0);
}

// Without a previous plan the stop of an invalid scene is a standstill at the
// origin: nothing of the rejected scene (here a position 1e6 m away) returns.
TEST_CASE("planner: an invalid first scene gets a standstill, not its own state") {
  auto planner = std::make_unique<itp::planner::Planner>();
  auto plan = std::make_unique<itp::planner::Plan>();
  auto scene = std::make_unique<itp::scene::Scene>(road_scene(1, 0));
  scene->ego.state.x = 1e6;  // off the reference line: still a position, the speed is rejected
  scene->ego.state.v = 500;  // above 70 m/s
  planner->plan({scene.get(), 0.0}, *plan);
  REQUIRE(plan->status == itp::PlanStatus::kInvalidInput);
  REQUIRE(plan->trajectory.size() > 1);
  for (const auto& p : plan->trajectory) {
    CHECK(p.v == 0.0);
    CHECK(p.x == 0.0);
    CHECK(p.y == 0.0);
  }
}

// The repeat rule must not hide a change: the same time with a faster ego is
// planned anew.
TEST_CASE("planner: a changed scene at the same time is planned anew") {
  auto planner = std::make_unique<itp::planner::Planner>();
  auto plan = std::make_unique<itp::planner::Plan>();
  auto scene = std::make_unique<itp::scene::Scene>(road_scene(1, 0));
  planner->plan({scene.get(), 0.0}, *plan);
  REQUIRE(plan->status == itp::PlanStatus::kOk);
  const double v_first = plan->trajectory[0].v;
  scene->ego.state.v = 5.0;
  planner->plan({scene.get(), 0.0}, *plan);
  REQUIRE(plan->status == itp::PlanStatus::kOk);
  CHECK(plan->trajectory[0].v == doctest::Approx(5.0).epsilon(0.05));
  CHECK(plan->trajectory[0].v != doctest::Approx(v_first));
}

// A blocked road: the fallback, asked twice, is the same stop.
TEST_CASE("planner: the same blocked scene twice gives the same safe stop") {
  auto planner = std::make_unique<itp::planner::Planner>();
  auto first = std::make_unique<itp::planner::Plan>();
  auto second = std::make_unique<itp::planner::Plan>();
  auto scene = std::make_unique<itp::scene::Scene>(road_scene(0, 0));
  add_static(*scene, 1, 30, 0.0, 0.0, 4.0, 3.6);  // across the only lane
  planner->plan({scene.get(), 0.0}, *first);
  REQUIRE(first->status == itp::PlanStatus::kFallback);
  planner->plan({scene.get(), 0.0}, *second);
  REQUIRE(second->status == itp::PlanStatus::kFallback);
  CHECK(second->fallback == first->fallback);
  REQUIRE(second->trajectory.size() == first->trajectory.size());
  CHECK(std::memcmp(first->trajectory.data(), second->trajectory.data(),
                    first->trajectory.size() * sizeof(itp::planner::TrajectoryPoint)) == 0);
}
