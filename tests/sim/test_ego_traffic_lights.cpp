// The ego's own traffic lights (sim/ego_traffic_lights.hpp): which light puts
// a stop wall into the planner's scene, where, and the closed loop stopping
// at a red light and going on at green.
#include <doctest/doctest.h>

#include <cmath>
#include <optional>
#include <string>

#include "itp/configurations.hpp"
#include "itp/scene/validation.hpp"
#include "sim/box_geometry.hpp"
#include "sim/closed_loop.hpp"
#include "sim/ego_traffic_lights.hpp"
#include "sim/inproc_endpoint.hpp"
#include "sim/scene_convert.hpp"

using namespace hil::sim;

namespace {

// Straight two-lane road along +x (the ego's lane on y = 0, the left one on
// y = 3.5), and the ego's lane up to x = 100 with a light at its end: red for
// `red` s, then green for 20 s, then yellow for 3 s.
World light_road(double red, double ego_x, double v) {
  World w;
  w.name = "test-light";
  for (double x = 0.0; x <= 300.0 + 1e-9; x += 2.0) w.reference_line.push_back({x, 0.0});
  w.road.lane_width = 3.5;
  w.road.left_boundary = Boundary::constant_at(5.25);
  w.road.right_boundary = Boundary::constant_at(-1.75);
  w.road.speed_limit = 12;
  w.ego.x = ego_x;
  w.ego.v = v;
  Lane lane;
  lane.id = 7;
  lane.centre = {{0, 0}, {50, 0}, {100, 0}};
  lane.left = {{0, 1.75}, {100, 1.75}};
  lane.right = {{0, -1.75}, {100, -1.75}};
  lane.traffic_lights.push_back(TrafficLightCycle{{{"red", red}, {"green", 20.0}, {"yellow", 3.0}}, 0.0});
  lane.stop_s = 100.0;
  w.lanes.push_back(lane);
  return w;
}

// The ego's front bumper x on this road.
double front_x(const World& w, const Pose& rear_axle) {
  const OrientedBox b = ego_box(rear_axle, w.ego.length, w.ego.width, w.ego.wheelbase);
  return b.cx + 0.5 * b.length * std::cos(b.heading);
}

std::optional<StopWall> wall_at(const World& w, double now) {
  return ego_stop_wall(w, LaneMap(w.lanes), polyline_arc_lengths(w.reference_line), ego_at_start(w), now);
}

}  // namespace

TEST_CASE("ego lights: a red light on the route is a wall across the road just past its stop line") {
  const World w = light_road(10.0, 50.0, 10.0);
  const std::optional<StopWall> wall = wall_at(w, 1.0);
  REQUIRE(wall.has_value());
  CHECK(wall->lane == 7);
  CHECK(wall->line_s == doctest::Approx(100.0));
  CHECK(wall->box.id == kStopWallIdBase + 0);
  CHECK(wall->box.x - 0.5 * wall->box.length == doctest::Approx(100.0));  // its near face on the line
  CHECK(wall->box.heading == doctest::Approx(0.0));
  // Across the whole drivable road (-1.75 .. 5.25), 0.5 m beyond each edge.
  CHECK(wall->box.y - 0.5 * wall->box.width == doctest::Approx(-2.25));
  CHECK(wall->box.y + 0.5 * wall->box.width == doctest::Approx(5.75));
}

TEST_CASE("ego lights: green, a light behind the ego, a neighbour lane's or an oncoming lane's light: no wall") {
  CHECK_FALSE(wall_at(light_road(10.0, 50.0, 10.0), 12.0).has_value());   // green
  CHECK_FALSE(wall_at(light_road(10.0, 120.0, 10.0), 1.0).has_value());  // the line is behind
  World beside = light_road(10.0, 50.0, 10.0);
  for (Point2& p : beside.lanes[0].centre) p.y = 3.5;  // the left lane's light
  CHECK_FALSE(wall_at(beside, 1.0).has_value());
  World oncoming = light_road(10.0, 50.0, 10.0);
  oncoming.lanes[0].centre = {{200, 0}, {150, 0}, {100, 0}};  // ends at x = 100 heading -x
  CHECK_FALSE(wall_at(oncoming, 1.0).has_value());
}

TEST_CASE("ego lights: red stops the ego while its braking limit can; yellow only when comfortable") {
  // Red: at 10 m/s, 6 m/s^2 needs 8.3 m. Front bumper 5 m before the line: committed, no wall.
  World close = light_road(10.0, 0.0, 10.0);
  close.ego.x = 100.0 - (front_x(close, Pose{0, 0, 0}) - 0.0) - 5.0;
  CHECK_FALSE(wall_at(close, 1.0).has_value());
  close.ego.x -= 5.0;  // 10 m before: 5 m/s^2 stops it
  CHECK(wall_at(close, 1.0).has_value());
  // Yellow (t = 30..33 s): 10 m before needs 5 m/s^2 (> 3: drive on); 20 m before, 2.5 m/s^2: stop.
  CHECK_FALSE(wall_at(close, 31.0).has_value());
  close.ego.x -= 10.0;
  CHECK(wall_at(close, 31.0).has_value());
}

TEST_CASE("ego lights: the planner's scene holds the wall first, and it validates") {
  const World w = light_road(10.0, 50.0, 10.0);
  itp::scene::Scene s;
  const ConvertResult res = make_planner_scene(w, ego_at_start(w), 1.0, Prediction::kLane, s);
  REQUIRE(res.ok);
  REQUIRE(res.stop_wall_lane.has_value());
  CHECK(*res.stop_wall_lane == 7);
  REQUIRE(s.static_obstacles.size() == 1);
  CHECK(s.static_obstacles[0].id == kStopWallIdBase);
  CHECK(itp::scene::validate(s).ok());
  itp::scene::Scene green;
  CHECK_FALSE(make_planner_scene(w, ego_at_start(w), 12.0, Prediction::kLane, green).stop_wall_lane.has_value());
  CHECK(green.static_obstacles.empty());
}

TEST_CASE("ego lights, closed loop: the ego stops before the red light's line and goes on at green") {
  // Red for 9 s; at 10 m/s from x = 30 the ego reaches the line after about 6 s.
  const World w = light_road(9.0, 30.0, 10.0);
  InprocEndpoint ep;
  RunOptions opt;
  opt.duration = 16.0;
  const SceneRunResult r = run_scene(w, ep, opt);
  CHECK(r.error.empty());
  CHECK_FALSE(r.summary.collided());
  CHECK_FALSE(r.summary.departed());
  double front_while_red = 0.0;
  for (const auto& q : r.trace) {
    if (q.t < 9.0) front_while_red = std::max(front_while_red, front_x(w, q.pose));
  }
  CHECK(front_while_red < 100.0);   // stopped before the line
  CHECK(front_while_red > 90.0);    // but close to it
  CHECK(front_x(w, r.trace.back().pose) > 110.0);  // and through after green
  int walls = 0;
  for (const CycleRecord& c : r.cycles) walls += c.stop_wall_lane.has_value() && c.t < 9.0 ? 1 : 0;
  CHECK(walls > 0);  // the cycles that sent it say so (the trace's "stop_wall_lane")
  std::string reasons;
  for (const CycleRecord& c : r.cycles) {
    if (c.stop_wall_lane && reasons.find(c.reason) == std::string::npos) reasons += " [" + c.reason + "]";
  }
  MESSAGE("cycles with the wall: " << walls << "; fallback reasons while it stood:" << reasons);
  MESSAGE("front before the line while red: " << front_while_red << " m; at the end: "
                                              << front_x(w, r.trace.back().pose) << " m");
}
