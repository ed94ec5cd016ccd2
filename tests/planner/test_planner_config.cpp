// The planner is a template on its configuration: the same scenarios planned
// with CompactConfig (60 m / 5 s horizons, 4 static + 2 dynamic obstacles,
// 12 path blocks, 10 speed blocks) must give physically valid plans of that
// configuration's shape, with memory that follows its sizes.
#include <doctest/doctest.h>

#include <array>
#include <cstring>
#include <memory>

#include "itp/configurations.hpp"
#include "itp/link/planner_messages.hpp"
#include "itp/planner/planner.hpp"
#include "plan_checks.hpp"
#include "scene_builder.hpp"

using itp::CompactConfig;
using itp::DefaultConfig;
using CompactPlanner = itp::planner::BasicPlanner<CompactConfig>;
using CompactScene = itp::scene::BasicScene<CompactConfig>;
using CompactPlan = itp::planner::BasicPlan<CompactConfig>;
using namespace planner_test;

using CompactRun = PlanRun<CompactConfig>;

TEST_CASE("configuration: the compact planner's memory follows its sizes") {
  static_assert(CompactConfig::kTrajectorySamples == 51, "5 s every 0.1 s");
  static_assert(CompactConfig::kPathVariables == 39 && CompactConfig::kSpeedVariables == 33);
  static_assert(CompactConfig::kMaxObstacles == 6 && CompactConfig::kMaxSlices == 17);
  // About half (x86-64: 149 736 of 298 632 B since the default's zone table
  // holds its tight bound, 384 zones; below half before): well under 60 %.
  CHECK(sizeof(CompactPlanner) * 5 < sizeof(itp::planner::Planner) * 3);
  CHECK(sizeof(CompactScene) < sizeof(itp::scene::Scene));
  MESSAGE("sizeof planner: default " << sizeof(itp::planner::Planner) << " B, compact "
                                     << sizeof(CompactPlanner) << " B");
}

TEST_CASE("configuration: shared QP storage is lent between cycles and a plan takes it back") {
  using LowRamPlanner = itp::planner::BasicPlanner<itp::LowRamConfig>;
  static_assert(itp::planner::Planner::kLendableBytes == 0, "one storage per QP: nothing to lend");
  auto unshared = std::make_unique<itp::planner::Planner>();
  const int asker = 0;
  CHECK(unshared->lend(&asker).empty());
  CHECK_FALSE(unshared->lent_to(&asker));
  static_assert(LowRamPlanner::kLendableBytes >= sizeof(itp::qp::QpStorage<itp::qp::PathQpDims<itp::Scalar, itp::LowRamConfig>>));
  auto planner = std::make_unique<LowRamPlanner>();
  const auto scene = road_scene<itp::scene::BasicScene<itp::LowRamConfig>>(1, 0);
  const int borrower = 0;
  const auto bytes = planner->lend(&borrower);
  CHECK(bytes.size() == LowRamPlanner::kLendableBytes);
  std::memset(bytes.data(), 0xA5, bytes.size());  // what a borrower leaves there must not matter
  CHECK(planner->lent_to(&borrower));
  const auto& first = planner->plan({&scene, 0});
  CHECK_FALSE(planner->lent_to(&borrower));
  REQUIRE(first.status == itp::PlanStatus::kOk);
  // The same as a planner whose storage was never lent.
  auto fresh = std::make_unique<LowRamPlanner>();
  const auto& expected = fresh->plan({&scene, 0});
  REQUIRE(first.trajectory.size() == expected.trajectory.size());
  for (std::size_t k = 0; k < expected.trajectory.size(); ++k) {
    CHECK(first.trajectory[k].x == expected.trajectory[k].x);
    CHECK(first.trajectory[k].v == expected.trajectory[k].v);
  }
}

TEST_CASE("configuration: compact planner cruises a free road over its own horizon") {
  const auto s = road_scene<CompactScene>(1, 0);
  CompactRun r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(r.plan->trajectory.back().t == doctest::Approx(5.0));
  CHECK(r.plan->trajectory.back().v == doctest::Approx(15).epsilon(0.05));
  for (const auto& q : r.plan->trajectory) {
    CHECK(std::fabs(q.l) < 0.1);
  }
  CHECK(r.plan->iterations <= CompactConfig::kMaxPlannerIterations);
}

TEST_CASE("configuration: compact planner passes a static obstacle with clearance") {
  auto s = road_scene<CompactScene>(1, 0);
  add_static(s, 1, 35, 0.2);
  CompactRun r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(min_clearance(s, *r.plan) >= 0.2);
  CHECK(decision_for(*r.plan, 1).lateral == itp::planner::LateralSide::kLeft);
}

TEST_CASE("configuration: compact planner follows a slow leader") {
  auto s = road_scene<CompactScene>(0, 0);
  add_mover(s, 7, 30, 0, 0, 6);
  CompactRun r;
  r.go(s);
  REQUIRE(r.status == itp::PlanStatus::kOk);
  check_limits(s, *r.plan);
  CHECK(min_clearance(s, *r.plan) >= 4.0);
}

TEST_CASE("configuration: identical input gives bit-identical output with the compact planner") {
  auto s = road_scene<CompactScene>(1, 0);
  add_static(s, 1, 35, 0.2);
  add_mover(s, 2, 50, 3.5, 3.14159, 8);
  CompactRun a;
  CompactRun b;
  a.go(s);
  b.go(s);
  REQUIRE(a.plan->trajectory.size() == b.plan->trajectory.size());
  CHECK(std::memcmp(a.plan->trajectory.data(), b.plan->trajectory.data(),
                    a.plan->trajectory.size() * sizeof(itp::planner::TrajectoryPoint)) == 0);
}

TEST_CASE("configuration: a scene beyond the compact capacities is rejected by the decoder") {
  auto big = road_scene<itp::scene::Scene>(1, 0);
  for (int i = 0; i < CompactConfig::kMaxStaticObstacles + 1; ++i) {
    add_static(big, 10 + i, 30.0 + 10.0 * i, 3.5);
  }
  std::array<std::uint8_t, itp::link::kMaxSceneBytes<itp::DefaultConfig>> buf{};
  const std::size_t n = itp::link::encode_scene(itp::link::SceneHeader{}, big, 1, buf);
  REQUIRE(n > 0);
  auto compact = std::make_unique<CompactScene>();
  itp::link::SceneHeader h;
  CHECK_FALSE(itp::link::decode_scene(std::span<const std::uint8_t>(buf.data(), n), h, *compact));
  auto same = std::make_unique<itp::scene::Scene>();
  CHECK(itp::link::decode_scene(std::span<const std::uint8_t>(buf.data(), n), h, *same));
}
