// The world -> planner Scene conversion: the example scene/1 files read,
// convert and validate; windows, boundaries and predictions are as specified;
// capacity overflow is reported, never truncated silently.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "itp/scene/validation.hpp"
#include "sim/scene_convert.hpp"
#include "sim/world.hpp"

using namespace hil::sim;

namespace {
World load(const std::string& name) {
  const auto r = load_scene_file(std::string(ITP_SCENE_DATA_DIR) + "/" + name);
  REQUIRE_MESSAGE(r.world.has_value(), r.error);
  return *r.world;
}
}  // namespace

TEST_CASE("the example scenes convert into valid planner scenes") {
  for (const char* name : {"free_road.json", "curved_road.json", "busy_10_static_5_dynamic.json"}) {
    CAPTURE(name);
    const World w = load(name);
    itp::scene::Scene s;
    const auto res = make_planner_scene(w, ego_at_start(w), 0.0, Prediction::kGroundTruth, s);
    REQUIRE_MESSAGE(res.ok, res.error);
    const auto v = itp::scene::validate(s);
    CHECK_MESSAGE(v.ok(), itp::scene::to_string(v.reason));
  }
  const World busy = load("busy_10_static_5_dynamic.json");
  itp::scene::Scene s;
  REQUIRE(make_planner_scene(busy, ego_at_start(busy), 0.0, Prediction::kGroundTruth, s).ok);
  CHECK(s.static_obstacles.size() == 10);
  CHECK(s.dynamic_obstacles.size() == 5);
}

TEST_CASE("a long reference line is cut to a window around the ego, boundaries shifted with it") {
  World w;
  w.name = "long";
  for (int i = 0; i <= 400; ++i) w.reference_line.push_back({2.0 * i, 0.0});  // 800 m
  w.road.lane_width = 3.5;
  w.road.left_boundary = Boundary{0.0, {{0.0, 5.25}, {300.0, 5.25}, {320.0, 1.75}}};
  w.road.right_boundary = Boundary::constant_at(-1.75);
  w.road.speed_limit = 15;
  w.ego.x = 250;
  w.ego.v = 10;
  itp::scene::Scene s;
  const auto res = make_planner_scene(w, ego_at_start(w), 0.0, Prediction::kGroundTruth, s);
  REQUIRE_MESSAGE(res.ok, res.error);
  CHECK(s.reference_line.size() <=
        static_cast<std::size_t>(itp::DefaultConfig::kMaxReferencePoints));
  CHECK(s.reference_line[0].x <= 250 - 10);
  CHECK(s.reference_line.back().x >= 250 + 100);
  // The boundary narrows at world s = 300..320, i.e. window s = 300 - s0.
  CHECK(s.road.left.at(300 - res.window_s0) == doctest::Approx(5.25));
  CHECK(s.road.left.at(320 - res.window_s0) == doctest::Approx(1.75));
  CHECK(itp::scene::validate(s).ok());
}

TEST_CASE("predictions: ground truth from now, or constant velocity from the current state") {
  World w;
  for (int i = 0; i <= 100; ++i) w.reference_line.push_back({2.0 * i, 0.0});
  w.road.left_boundary = Boundary::constant_at(5.25);
  w.road.right_boundary = Boundary::constant_at(-1.75);
  w.road.speed_limit = 15;
  DynamicObstacle cut_in;
  cut_in.id = 4;
  cut_in.length = 4.5;
  cut_in.width = 1.8;
  for (int k = 0; k <= 200; ++k) {  // 20 s: longer than the planner holds, windowed from now
    const double t = 0.1 * k;
    cut_in.trajectory.push_back({t, 30 + 8 * t, std::max(0.0, 3.5 - 0.5 * t), 0.0, 8.0});
  }
  w.dynamic_obstacles.push_back(cut_in);
  itp::scene::Scene truth;
  itp::scene::Scene cv;
  const EgoNow ego = ego_at_start(w);
  REQUIRE(make_planner_scene(w, ego, 2.0, Prediction::kGroundTruth, truth).ok);
  REQUIRE(make_planner_scene(w, ego, 2.0, Prediction::kConstantVelocity, cv).ok);
  REQUIRE(truth.dynamic_obstacles.size() == 1);
  const auto& t4 = truth.dynamic_obstacles[0].trajectory;
  CHECK(t4[0].t == doctest::Approx(2.0));  // scene time
  CHECK(t4[0].x == doctest::Approx(46));
  CHECK(t4[10].y == doctest::Approx(2.0));   // still moving in: 3.5 - 0.5 * 3
  const auto& c4 = cv.dynamic_obstacles[0].trajectory;
  CHECK(c4[10].y == doctest::Approx(2.5));   // constant heading along +x: y stays
  CHECK(c4[10].x == doctest::Approx(54));
}

TEST_CASE("more obstacles in range than the planner holds is an error, not a truncation") {
  World w;
  for (int i = 0; i <= 100; ++i) w.reference_line.push_back({2.0 * i, 0.0});
  w.road.left_boundary = Boundary::constant_at(5.25);
  w.road.right_boundary = Boundary::constant_at(-1.75);
  w.road.speed_limit = 15;
  for (int i = 0; i < itp::DefaultConfig::kMaxStaticObstacles + 1; ++i) {
    w.static_obstacles.push_back({i + 1, 20.0 + 5 * i, 3.5, 0.0, 1.0, 1.0, ""});
  }
  itp::scene::Scene s;
  const auto res = make_planner_scene(w, ego_at_start(w), 0.0, Prediction::kGroundTruth, s);
  CHECK_FALSE(res.ok);
  CHECK(res.error.find("static") != std::string::npos);
}
