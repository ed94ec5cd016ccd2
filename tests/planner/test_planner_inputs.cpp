// Issue 13, the planner's share of defects 1, 2 and 11. The firmware service
// already refuses a bad scene time and never plans an invalid scene
// (tests/app/test_service_link.cpp); the planner called directly (inproc,
// planner_cli) still needs the changes named in each skip decorator. Run
// them with --no-skip to see them fail.
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

// Needs: BasicPlanner::prepare() validates with scene::validate(scene, now)
// (the two-argument form) instead of validate(scene).
TEST_CASE("planner: a scene time that is NaN, infinite or negative is invalid_input" *
          doctest::skip(true)) {
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

// Needs: BasicPlanner::fallback() for invalid_input starts the stop from the
// last valid state (the previous ok plan at `now`) or, without one, is a
// standstill (v = 0 at the last valid position); never from the rejected
// ego state (planner.cpp: `v0 = scene->ego.state.v` when finite).
TEST_CASE("planner: the stop of an invalid scene never runs at the rejected ego speed" * doctest::skip(true)) {
  auto planner = std::make_unique<itp::planner::Planner>();
  auto plan = std::make_unique<itp::planner::Plan>();
  auto scene = std::make_unique<itp::scene::Scene>(road_scene(1, 0));
  planner->plan({scene.get(), 0.0}, *plan);
  REQUIRE(plan->status == itp::PlanStatus::kOk);
  scene->ego.state.v = 1e9;  // rejected: above 70 m/s
  planner->plan({scene.get(), 0.1}, *plan);
  REQUIRE(plan->status == itp::PlanStatus::kInvalidInput);
  for (const auto& p : plan->trajectory) {
    CHECK(p.v <= 10.0 + 1e-9);  // at most the last valid speed (10 m/s), braking from there
    CHECK(std::fabs(p.x) < 1e3);
  }
}

// Issue 13, defect 11: the same scene sent twice (no reset) must give the
// same plan. Needs: the planner's stitching/hysteresis to be a fixed point
// for an unchanged scene at an unchanged time (today the second call
// stitches onto the first call's plan at age 0 and the decision hysteresis
// flips, so calls alternate between two plans).
TEST_CASE("planner: the same scene twice gives the same plan" * doctest::skip(true)) {
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
