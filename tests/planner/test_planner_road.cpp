// The road configuration (itp/configurations.hpp): a sensor-fusion object
// list of up to 32 static and 32 moving objects arrives whole; the decision
// stage gets the most relevant (10 + 5), the ST graph and the collision
// check every object.
#include <doctest/doctest.h>

#include <cmath>
#include <memory>

#include "itp/configurations.hpp"
#include "itp/geometry/reference_line.hpp"
#include "itp/geometry/smoothing_spline.hpp"
#include "itp/planner/planner.hpp"
#include "itp/planner/sl_scene.hpp"
#include "plan_checks.hpp"
#include "scene_builder.hpp"

using itp::RoadConfig;
using RoadScene = itp::scene::BasicScene<RoadConfig>;
using RoadRun = planner_test::PlanRun<RoadConfig>;
using namespace planner_test;

static_assert(RoadConfig::kMaxStaticObstacles == 32 && RoadConfig::kMaxDynamicObstacles == 32);
static_assert(RoadConfig::kDecisionStatics == 10 && RoadConfig::kDecisionDynamics == 5);
static_assert(RoadConfig::kMaxDecisionObstacles == itp::DefaultConfig::kMaxDecisionObstacles,
              "the decision stage keeps the paper's envelope");

namespace {

// Constant velocity along +x, sampled every 0.2 s (the road configuration's
// 40 prediction samples cover 7.8 s).
void add_cruiser(RoadScene& s, int id, double x, double y, double v) {
  typename decltype(s.dynamic_obstacles)::value_type o;
  o.id = id;
  o.length = 4.5;
  o.width = 1.8;
  for (int k = 0; k < RoadConfig::kMaxPredictionSamples; ++k) {
    itp::scene::TimedPose p;
    p.t = 0.2 * k;
    p.x = x + v * p.t;
    p.y = y;
    p.v = v;
    REQUIRE(o.trajectory.push_back(p));
  }
  REQUIRE(s.dynamic_obstacles.push_back(o));
}

}  // namespace

TEST_CASE("road configuration: of 24 parked cars the decision stage gets the ones on the road, nearest first") {
  // 22 cars parked beyond the right road edge (off the drivable area) every
  // 8 m, and two in the lanes ahead at 60 m (right lane) and 95 m (left lane).
  RoadScene s = road_scene<RoadScene>(1, 0, 0, 250);
  for (int i = 0; i < 22; ++i) add_static(s, 100 + i, 20 + 8 * i, -3.5, 0, 4.5, 1.8);
  add_static(s, 1, 60, 0.0);
  add_static(s, 2, 95, 3.5);
  itp::geometry::BasicSmoothingSplineWorkspace<RoadConfig> ws;
  auto line = std::make_unique<itp::geometry::BasicReferenceLine<RoadConfig>>();
  REQUIRE(line->build(s.reference_line.span(), ws) == itp::geometry::ReferenceLineStatus::kOk);
  auto sl = std::make_unique<itp::planner::BasicSlScene<RoadConfig>>();
  sl->build(s, *line, 0, 0, 150, itp::planner::PlannerSettings{});
  REQUIRE(sl->boxes().size() == 10);
  CHECK(sl->statics_left_out() == 14);
  bool have1 = false, have2 = false;
  for (const auto& b : sl->boxes()) {
    have1 = have1 || b.obstacle_id == 1;
    have2 = have2 || b.obstacle_id == 2;
  }
  CHECK(have1);
  CHECK(have2);

  // The plan passes both on the road and touches none of the 24.
  RoadRun r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(min_clearance(s, *r.plan) >= 0.3);
}

TEST_CASE("road configuration: 12 moving objects, all in the ST graph; the ego follows its leader") {
  // A slow leader in the ego's lane 40 m ahead, 8 cars at the ego's speed in
  // the left lane, 3 cars far ahead in the left lane.
  RoadScene s = road_scene<RoadScene>(1, 0, 0, 300);
  s.ego.state.v = 12;
  add_cruiser(s, 50, 40, 0.0, 6.0);
  for (int i = 0; i < 8; ++i) add_cruiser(s, 60 + i, 25 + 12 * i, 3.5, 12.0);
  for (int i = 0; i < 3; ++i) add_cruiser(s, 70 + i, 180 + 20 * i, 3.5, 10.0);
  RoadRun r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(min_clearance(s, *r.plan) >= 0.5);
  CHECK(r.planner->st_graph().decisions().size() == 12);
  CHECK(decision_for(*r.plan, 50).longitudinal == itp::speed::Longitudinal::kFollow);
  // Behind the leader all along: the front bumper stays behind its rear.
  for (const auto& q : r.plan->trajectory) {
    CHECK(q.x + s.ego.geometry.length - rear_overhang(s) < 40 + 6.0 * q.t - 2.25);
  }
}
