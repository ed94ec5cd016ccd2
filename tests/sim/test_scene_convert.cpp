// The world -> planner Scene conversion: the example scene/1 files read,
// convert and validate; windows, boundaries and predictions are as specified;
// long roads are resampled to the configuration's capacities within their
// documented bounds; more obstacles than it holds keep the most relevant ones
// and count the others.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "itp/configurations.hpp"
#include "itp/geometry/reference_line.hpp"
#include "itp/scene/validation.hpp"
#include "sim/box_geometry.hpp"
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

namespace {

World open_road() {
  World w;
  for (int i = 0; i <= 100; ++i) w.reference_line.push_back({2.0 * i, 0.0});
  w.road.left_boundary = Boundary::constant_at(5.25);
  w.road.right_boundary = Boundary::constant_at(-1.75);
  w.road.speed_limit = 15;
  w.ego.v = 10;
  return w;
}

bool has_static(const itp::scene::Scene& s, int id) {
  return std::any_of(s.static_obstacles.begin(), s.static_obstacles.end(), [&](const auto& o) { return o.id == id; });
}
bool has_dynamic(const itp::scene::Scene& s, int id) {
  return std::any_of(s.dynamic_obstacles.begin(), s.dynamic_obstacles.end(), [&](const auto& o) { return o.id == id; });
}

// A winding road sampled every 0.5 m (400 m: the window holds ~300 points),
// with a left edge of 1 m knots that steps where a lane starts and ends.
World winding_road() {
  World w;
  w.name = "winding";
  for (double s = 0.0; s <= 400.0; s += 0.5) {
    w.reference_line.push_back({s, 12.0 * std::sin(s / 35.0)});
  }
  for (double s = 0.0; s <= 400.0; s += 1.0) {
    const double extra = (s > 120.0 && s < 180.0) ? 3.5 : 0.0;  // a lane on the left for 60 m
    w.road.left_boundary.knots.push_back({s, 5.25 + extra + 0.05 * std::sin(s)});
    w.road.right_boundary.knots.push_back({s, -1.75 - 0.05 * std::cos(1.3 * s)});
  }
  w.road.speed_limit = 15;
  w.ego.x = 100.0;
  w.ego.y = 12.0 * std::sin(100.0 / 35.0);
  w.ego.heading = std::atan(12.0 / 35.0 * std::cos(100.0 / 35.0));
  w.ego.v = 10;
  return w;
}

}  // namespace

TEST_CASE("more obstacles in range than the scene holds: the most relevant are kept, the rest counted") {
  World w = open_road();
  // Obstacles 1..10 beside the road (3.5 m left of the ego lane), 11..14 in the ego's lane ahead.
  for (int i = 0; i < 10; ++i) w.static_obstacles.push_back({i + 1, 20.0 + 8 * i, 7.5, 0.0, 1.0, 1.0, ""});
  for (int i = 0; i < 4; ++i) w.static_obstacles.push_back({11 + i, 30.0 + 15 * i, 0.0, 0.0, 1.0, 1.0, ""});
  itp::scene::Scene s;
  const auto res = make_planner_scene(w, ego_at_start(w), 0.0, Prediction::kGroundTruth, s);
  REQUIRE(res.ok);
  CHECK(s.static_obstacles.size() == static_cast<std::size_t>(itp::DefaultConfig::kMaxStaticObstacles));
  CHECK(res.static_left_out == 4);
  CHECK(res.left_out() == 4);
  for (int id = 11; id <= 14; ++id) CHECK(has_static(s, id));  // in the ego's path: kept
  // Beside the road, the farthest ahead are left out (the ego passes the nearer ones within the horizon).
  CHECK_FALSE(has_static(s, 10));
  CHECK_FALSE(has_static(s, 9));
  CHECK(has_static(s, 1));
  CHECK(itp::scene::validate(s).ok());
}

TEST_CASE("dynamic obstacles beyond the capacity: the car close behind, which a braking ego would meet, outranks traffic alongside") {
  World w = open_road();
  w.ego.x = 60.0;
  auto car = [](int id, double x, double y, double v) {
    DynamicObstacle d;
    d.id = id;
    d.length = 4.5;
    d.width = 1.8;
    d.trajectory.push_back({0.0, x, y, 0.0, v});
    return d;
  };
  // 25 m behind in the ego's lane at the ego's speed: 20 m away as long as the
  // ego cruises, but it meets the ego if the ego brakes (stopped after 12.5 m).
  w.dynamic_obstacles.push_back(car(1, 35.0, 0.0, 10.0));
  // Six cars around the ego in the next lane (1.65 m gap), at the ego's speed,
  // each nearer than that follower to the cruising ego (at most 14 m), and one far ahead.
  for (int i = 0; i < 6; ++i) w.dynamic_obstacles.push_back(car(10 + i, 50.0 + 6.0 * i, 3.5, 10.0));
  w.dynamic_obstacles.push_back(car(20, 150.0, 0.0, 15.0));
  itp::scene::Scene s;
  const auto res = make_planner_scene(w, ego_at_start(w), 0.0, Prediction::kConstantVelocity, s);
  REQUIRE(res.ok);
  CHECK(res.dynamic_left_out == 3);
  CHECK(has_dynamic(s, 1));
  CHECK(has_dynamic(s, 12));        // right beside the ego
  CHECK_FALSE(has_dynamic(s, 20));  // far ahead and pulling away
  CHECK_FALSE(has_dynamic(s, 15));  // the farthest in the next lane
}

TEST_CASE("a long winding window is resampled to the capacities within the documented bounds") {
  const World w = winding_road();
  itp::scene::Scene s;
  const auto res = make_planner_scene(w, ego_at_start(w), 0.0, Prediction::kGroundTruth, s);
  REQUIRE_MESSAGE(res.ok, res.error);
  CHECK(s.reference_line.size() <= static_cast<std::size_t>(itp::DefaultConfig::kMaxReferencePoints));
  CHECK(s.road.left.table.size() <= static_cast<std::size_t>(itp::DefaultConfig::kMaxBoundaryPoints));
  CHECK(s.road.right.table.size() <= static_cast<std::size_t>(itp::DefaultConfig::kMaxBoundaryPoints));
  CHECK(itp::scene::validate(s).ok());
  CHECK(res.reference_deviation_m < 0.02);

  // The planner's own frame (its smoothing spline of the sent points) against
  // the world's polyline: the centre line within the deviation plus the
  // spline's smoothing (docs/frenet.md: < 5 mm on clean curves).
  auto line = std::make_unique<itp::geometry::ReferenceLine>();
  auto ws = std::make_unique<itp::geometry::SmoothingSplineWorkspace>();
  REQUIRE(line->build(s.reference_line.span(), *ws) ==
          itp::geometry::ReferenceLineStatus::kOk);
  const std::vector<double> arc = polyline_arc_lengths(w.reference_line);
  double centre_error = 0.0;
  double outside = 0.0;
  for (double sw = 1.0; sw < static_cast<double>(line->length()) - 1.0; sw += 0.25) {
    const auto c = line->to_cartesian({sw, 0.0});
    centre_error = std::max(centre_error, std::fabs(project_to_polyline(w.reference_line, c.x, c.y).l));
    // Both edges as the planner places them, read back in the world's frame.
    for (const bool left : {true, false}) {
      const double l = left ? s.road.left.at(sw) : s.road.right.at(sw);
      const auto p = line->to_cartesian({sw, l});
      const PolylineProjection pr = project_to_polyline(w.reference_line, p.x, p.y);
      const double truth = left ? w.road.left_boundary.at(pr.s) : w.road.right_boundary.at(pr.s);
      outside = std::max(outside, left ? pr.l - truth : truth - pr.l);
    }
  }
  MESSAGE("winding road: reference deviation ", res.reference_deviation_m, " m, planner centre vs world ", centre_error,
          " m, edges outside ", outside, " m, narrowing ", res.boundary_narrowing_m, " m");
  CHECK(centre_error <= res.reference_deviation_m + 0.005);
  // Never wider than the road, up to the frames' difference (spline vs polyline).
  CHECK(outside <= 0.005);
  CHECK(res.boundary_narrowing_m < 0.5);
}

TEST_CASE("the conversion takes its capacities from the receiving configuration") {
  World w = winding_road();
  for (int i = 0; i < 6; ++i) w.static_obstacles.push_back({i + 1, 110.0 + 6 * i, 12.0 * std::sin((110.0 + 6 * i) / 35.0), 0.0, 1.0, 1.0, ""});
  itp::scene::BasicScene<itp::CompactConfig> s;
  const auto res = make_planner_scene(w, ego_at_start(w), 0.0, Prediction::kGroundTruth, s);
  REQUIRE(res.ok);
  CHECK(s.reference_line.size() <= static_cast<std::size_t>(itp::CompactConfig::kMaxReferencePoints));
  CHECK(s.road.left.table.size() <= static_cast<std::size_t>(itp::CompactConfig::kMaxBoundaryPoints));
  CHECK(s.static_obstacles.size() == static_cast<std::size_t>(itp::CompactConfig::kMaxStaticObstacles));
  CHECK(res.static_left_out == 2);
  // The compact window is shorter: its longest SL horizon + 20 m ahead, 40 m behind.
  double length = 0.0;
  for (std::size_t i = 0; i + 1 < s.reference_line.size(); ++i) {
    length += std::hypot(s.reference_line[i + 1].x - s.reference_line[i].x, s.reference_line[i + 1].y - s.reference_line[i].y);
  }
  CHECK(length < static_cast<double>(itp::CompactConfig::kMaxPathLength) + 20.0 + 40.0 + 1.0);
  CHECK(length < static_cast<double>(itp::DefaultConfig::kMaxPathLength));
}

TEST_CASE("the road configuration: 32 + 32 objects and predictions every 0.2 s over the horizon") {
  CHECK(prediction_step<itp::DefaultConfig>() == doctest::Approx(0.1));
  CHECK(prediction_step<itp::RoadConfig>() == doctest::Approx(0.2));
  World w = open_road();
  for (int i = 0; i < 34; ++i) w.static_obstacles.push_back({i + 1, 20.0 + 4 * i, 7.5, 0.0, 1.0, 1.0, ""});
  for (int i = 0; i < 20; ++i) {
    DynamicObstacle d;
    d.id = 100 + i;
    d.length = 4.5;
    d.width = 1.8;
    d.trajectory.push_back({0.0, 15.0 + 6.0 * i, -3.5, 0.0, 8.0});
    d.trajectory.push_back({12.0, 15.0 + 6.0 * i + 96.0, -3.5, 0.0, 8.0});
    w.dynamic_obstacles.push_back(d);
  }
  auto s = std::make_unique<itp::scene::BasicScene<itp::RoadConfig>>();
  const auto res = make_planner_scene(w, ego_at_start(w), 1.0, Prediction::kConstantVelocity, *s);
  REQUIRE(res.ok);
  CHECK(s->static_obstacles.size() == 32);
  CHECK(res.static_left_out == 2);
  CHECK(s->dynamic_obstacles.size() == 20);
  CHECK(res.dynamic_left_out == 0);
  const auto& p = s->dynamic_obstacles[0].trajectory;
  REQUIRE(p.size() == 39);  // 0 ... 7.6 s every 0.2 s: the speed horizon + 0.5 s, within the 40 samples
  CHECK(p[0].t == doctest::Approx(1.0));
  CHECK(p[1].t - p[0].t == doctest::Approx(0.2));
  CHECK(p[38].t == doctest::Approx(1.0 + 7.6));
  CHECK(itp::scene::validate(*s).ok());
}
