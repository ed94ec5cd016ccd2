// The lane-following prediction (sim/lane_prediction.hpp, --prediction lane):
// an obstacle on a circular lane stays on the arc (where constant velocity
// leaves it along the tangent), its offset from the centre decays, a branch
// takes the straightest successor, and no match (off the map, a heading
// across the lane, a pedestrian, a world without lanes) is constant velocity.
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "itp/configurations.hpp"
#include "sim/lane_prediction.hpp"
#include "sim/scene_convert.hpp"
#include "sim/scene_generator.hpp"
#include "sim/world.hpp"

using namespace hil::sim;

namespace {

constexpr double kPi = std::numbers::pi;

// A lane on the circle of radius r about (cx, cy), counter-clockwise from
// angle a0 to a1, sampled every `step` metres, `width` wide.
Lane arc_lane(long id, double cx, double cy, double r, double a0, double a1, double width, double step = 2.0) {
  Lane lane;
  lane.id = id;
  const int n = static_cast<int>(std::ceil(r * (a1 - a0) / step));
  for (int k = 0; k <= n; ++k) {
    const double a = a0 + (a1 - a0) * k / n;
    auto at = [&](double rr) { return Point2{cx + rr * std::cos(a), cy + rr * std::sin(a)}; };
    lane.centre.push_back(at(r));
    lane.left.push_back(at(r - 0.5 * width));  // counter-clockwise: the centre of the circle is on the left
    lane.right.push_back(at(r + 0.5 * width));
  }
  return lane;
}

Lane straight_lane(long id, Point2 a, Point2 b, double width) {
  Lane lane;
  lane.id = id;
  const double h = std::atan2(b.y - a.y, b.x - a.x);
  const double nx = -std::sin(h) * 0.5 * width;
  const double ny = std::cos(h) * 0.5 * width;
  lane.centre = {a, b};
  lane.left = {{a.x + nx, a.y + ny}, {b.x + nx, b.y + ny}};
  lane.right = {{a.x - nx, a.y - ny}, {b.x - nx, b.y - ny}};
  return lane;
}

std::vector<double> times(double horizon, double step) {
  std::vector<double> t;
  for (int k = 0; k * step <= horizon + 1e-9; ++k) t.push_back(k * step);
  return t;
}

// A quarter circle of R = 40 m about the origin and its successor, the next
// quarter: 126 m of arc, the obstacle on the first one's centre.
std::vector<Lane> circle_lanes() {
  std::vector<Lane> lanes{arc_lane(1, 0, 0, 40, 0, kPi / 2, 3.5), arc_lane(2, 0, 0, 40, kPi / 2, kPi, 3.5)};
  lanes[0].successors = {2};
  return lanes;
}

}  // namespace

TEST_CASE("lane prediction: an obstacle on a circular lane stays on the arc at its speed, constant velocity leaves it") {
  const std::vector<Lane> lanes = circle_lanes();
  const LaneMap map(lanes);
  const double a0 = 0.2;  // [rad] where the obstacle is on the circle
  const Pose now{40 * std::cos(a0), 40 * std::sin(a0), a0 + kPi / 2};
  const double v = 10.0;
  const std::vector<double> t = times(7.5, 0.1);
  const auto pred = predict_along_lanes(map, now, v, t);
  REQUIRE(pred.has_value());
  REQUIRE(pred->size() == t.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    CAPTURE(t[k]);
    const Pose& p = (*pred)[k];
    const double r = std::hypot(p.x, p.y);
    CHECK(std::fabs(r - 40.0) < 0.02);  // the chord of a 2 m sample: c^2 / 8R = 1.3 cm
    const double angle = std::atan2(p.y, p.x);
    CHECK(std::fabs(wrap_angle(angle - (a0 + v * t[k] / 40.0))) * 40.0 < 0.05);  // 10 m/s along the arc
    CHECK(std::fabs(wrap_angle(p.heading - (angle + kPi / 2))) < 0.03);           // along the tangent
  }
  // The constant-velocity extrapolation of the same state ends 70 m along the
  // tangent: 20 m outside the circle, far off the 3.5 m lane.
  const double cv_x = now.x + v * 7.5 * std::cos(now.heading);
  const double cv_y = now.y + v * 7.5 * std::sin(now.heading);
  CHECK(std::hypot(cv_x, cv_y) - 40.0 > 20.0);
}

TEST_CASE("lane prediction: the offset from the centre line and the heading error decay, t = 0 is the obstacle itself") {
  const std::vector<Lane> lanes = circle_lanes();
  const LaneMap map(lanes);
  const Pose now{40.8, 0.0, kPi / 2 + 0.1};  // 0.8 m right of the centre line (outside), turned 0.1 rad left
  const std::vector<double> t = times(5.0, 0.5);
  const auto pred = predict_along_lanes(map, now, 8.0, t);
  REQUIRE(pred.has_value());
  CHECK((*pred)[0].x == now.x);
  CHECK((*pred)[0].y == now.y);
  CHECK((*pred)[0].heading == now.heading);
  for (std::size_t k = 1; k < t.size(); ++k) {
    CAPTURE(t[k]);
    const Pose& p = (*pred)[k];
    const double offset = std::hypot(p.x, p.y) - 40.0;  // > 0: right of the lane's direction
    const double expected = 0.8 * std::max(0.0, 1.0 - t[k] / kLateralOffsetDecay);
    CHECK(std::fabs(offset - expected) < 0.03);
    const double tangent = std::atan2(p.y, p.x) + kPi / 2;
    const double blend = std::max(0.0, 1.0 - t[k] / kHeadingBlendTime);
    CHECK(std::fabs(wrap_angle(p.heading - tangent) - 0.1 * blend) < 0.03);
  }
}

TEST_CASE("lane prediction: no match is no prediction (the caller's constant velocity)") {
  const std::vector<Lane> lanes = circle_lanes();
  const LaneMap map(lanes);
  const std::vector<double> t = times(2.0, 0.1);
  // Off the map: 5 m outside the lane.
  CHECK_FALSE(predict_along_lanes(map, Pose{45.0 + 1.75, 0.0, kPi / 2}, 5.0, t).has_value());
  // Within the tolerance outside the polygon: still the lane.
  CHECK(predict_along_lanes(map, Pose{40.0 + 1.75 + 0.4, 0.0, kPi / 2}, 5.0, t).has_value());
  // On the lane, but across it (60 degrees) or against it.
  CHECK_FALSE(predict_along_lanes(map, Pose{40.0, 0.0, kPi / 2 + 1.05}, 5.0, t).has_value());
  CHECK_FALSE(predict_along_lanes(map, Pose{40.0, 0.0, -kPi / 2}, 5.0, t).has_value());
  CHECK(predict_along_lanes(map, Pose{40.0, 0.0, kPi / 2 + 0.7}, 5.0, t).has_value());  // 40 degrees
  // An empty map.
  const std::vector<Lane> none;
  CHECK_FALSE(predict_along_lanes(LaneMap(none), Pose{40.0, 0.0, kPi / 2}, 5.0, t).has_value());
}

TEST_CASE("lane prediction: at a branch the straightest successor, beyond the map's end straight on") {
  // Lane 1 along +x to (20, 0); successors 2 (straight on to (60, 0)) and 3
  // (a left turn of R = 10 m), listed turn first.
  std::vector<Lane> lanes{straight_lane(1, {0, 0}, {20, 0}, 3.5), straight_lane(2, {20, 0}, {60, 0}, 3.5),
                          arc_lane(3, 20, 10, 10, -kPi / 2, 0, 3.5, 1.0)};
  lanes[0].successors = {3, 2};
  const LaneMap map(lanes);
  const auto m = map.match(Pose{5, 0.3, 0.0});
  REQUIRE(m.has_value());
  CHECK(lanes[m->lane].id == 1);
  CHECK(m->l == doctest::Approx(0.3));
  const LaneTrack track = map.track(*m, 100.0);
  REQUIRE(track.lanes.size() == 2);
  CHECK(track.lanes[1] == 2);
  // 80 m on: 25 m beyond the map's end at x = 60, still on y = 0, offset gone.
  const Pose far = track_pose(track, 80.0, 8.0);
  CHECK(far.x == doctest::Approx(85.0));
  CHECK(far.y == doctest::Approx(0.0));
  // Where lanes overlap, the one that runs the obstacle's way and holds it
  // nearest its centre line: on the turn 6 m into it, heading along the turn.
  const double a = -kPi / 2 + 0.6;
  const auto on_turn = map.match(Pose{20 + 10 * std::cos(a), 10 + 10 * std::sin(a), a + kPi / 2});
  REQUIRE(on_turn.has_value());
  CHECK(lanes[on_turn->lane].id == 3);
}

TEST_CASE("make_planner_scene: lane predictions follow the lane, a world without lanes gets exactly constant velocity") {
  // A generated scene has no lane map: kLane is kConstantVelocity, sample for sample.
  const World generated = generate_scene(1, 3);
  REQUIRE(generated.lanes.empty());
  REQUIRE_FALSE(generated.dynamic_obstacles.empty());
  auto cv = std::make_unique<itp::scene::Scene>();
  auto lane = std::make_unique<itp::scene::Scene>();
  for (double now : {0.0, 2.0, 5.0}) {
    REQUIRE(make_planner_scene(generated, ego_at_start(generated), now, Prediction::kConstantVelocity, *cv).ok);
    REQUIRE(make_planner_scene(generated, ego_at_start(generated), now, Prediction::kLane, *lane).ok);
    REQUIRE(cv->dynamic_obstacles.size() == lane->dynamic_obstacles.size());
    for (std::size_t i = 0; i < cv->dynamic_obstacles.size(); ++i) {
      const auto& a = cv->dynamic_obstacles[i];
      const auto& b = lane->dynamic_obstacles[i];
      REQUIRE(a.trajectory.size() == b.trajectory.size());
      for (std::size_t k = 0; k < a.trajectory.size(); ++k) {
        CHECK(a.trajectory[k].x == b.trajectory[k].x);
        CHECK(a.trajectory[k].y == b.trajectory[k].y);
        CHECK(a.trajectory[k].heading == b.trajectory[k].heading);
      }
    }
  }

  // A world on the R = 40 m circle with its lane map: the car ahead of the
  // ego is predicted along the arc; a pedestrian on the lane straight on.
  World w;
  w.name = "circle";
  for (int k = 0; k <= 126; ++k) {
    const double a = -0.5 + k / 40.0;
    w.reference_line.push_back({40 * std::cos(a), 40 * std::sin(a)});
  }
  w.road.lane_width = 3.5;
  w.road.left_boundary = Boundary::constant_at(1.75);
  w.road.right_boundary = Boundary::constant_at(-1.75);
  w.road.speed_limit = 15;
  w.ego.x = 40 * std::cos(-0.4);
  w.ego.y = 40 * std::sin(-0.4);
  w.ego.heading = -0.4 + kPi / 2;
  w.ego.v = 10;
  w.lanes = {arc_lane(1, 0, 0, 40, -0.6, kPi / 2, 3.5), arc_lane(2, 0, 0, 40, kPi / 2, kPi + 0.5, 3.5)};
  w.lanes[0].successors = {2};
  for (int id : {7, 8}) {
    DynamicObstacle d;
    d.id = id;
    d.length = id == 7 ? 4.5 : 0.8;
    d.width = id == 7 ? 1.8 : 0.8;
    d.kind = id == 7 ? "car" : "pedestrian";
    const double a = id == 7 ? 0.3 : 0.6;
    d.trajectory.push_back({0.0, 40 * std::cos(a), 40 * std::sin(a), a + kPi / 2, 8.0});
    w.dynamic_obstacles.push_back(d);
  }
  REQUIRE(make_planner_scene(w, ego_at_start(w), 0.0, Prediction::kLane, *lane).ok);
  REQUIRE(lane->dynamic_obstacles.size() == 2);
  for (const auto& d : lane->dynamic_obstacles) {
    CAPTURE(d.id);
    const auto& last = d.trajectory[d.trajectory.size() - 1];
    const double r = std::hypot(last.x, last.y);
    if (d.id == 7) {
      CHECK(std::fabs(r - 40.0) < 0.02);  // on the arc after 7.5 s (60 m)
    } else {
      CHECK(r - 40.0 > 20.0);  // the pedestrian: constant velocity, off along the tangent
    }
  }
}

TEST_CASE("scene/1 extension lanes: written and read back, malformed lanes are errors") {
  World w = generate_scene(1, 0);
  w.lanes = circle_lanes();
  const SceneParseResult back = parse_scene_text(scene_to_text(w));
  REQUIRE_MESSAGE(back.world.has_value(), back.error);
  REQUIRE(back.world->lanes.size() == 2);
  CHECK(back.world->lanes[0].id == 1);
  CHECK(back.world->lanes[0].successors == std::vector<long>{2});
  CHECK(back.world->lanes[1].centre.size() == w.lanes[1].centre.size());
  CHECK(back.world->lanes[1].left.back().x == w.lanes[1].left.back().x);
  CHECK(back.world->lanes[1].right.front().y == w.lanes[1].right.front().y);
  // Without lanes the key is absent (generated scenes' files are unchanged).
  CHECK(scene_to_text(generate_scene(1, 0)).find("\"lanes\"") == std::string::npos);
  std::string text = scene_to_text(w);
  const std::size_t at = text.find("\"centre\"");
  REQUIRE(at != std::string::npos);
  text.replace(at, 8, "\"middle\"");
  const SceneParseResult bad = parse_scene_text(text);
  CHECK_FALSE(bad.world.has_value());
  CHECK(bad.error.find("lanes[0]") != std::string::npos);
}

// --- Traffic lights (Lane::traffic_lights; CommonRoad 2020a <trafficLight>) ---

namespace {

// The colour at time step k of a CommonRoad cycle, as commonroad-io reads it
// (TrafficLight.get_state_at_time_step: the phase (k - offset) mod the
// cycle's length, counted from the first element), in integer time steps.
std::string commonroad_color(const std::vector<std::pair<std::string, long>>& cycle, long offset, long k) {
  long total = 0;
  for (const auto& c : cycle) total += c.second;
  long phase = ((k - offset) % total + total) % total;
  for (const auto& c : cycle) {
    if (phase < c.second) return c.first;
    phase -= c.second;
  }
  return "?";
}

// A straight lane along x from 0 to `end`, its stop line at `stop` under one light.
Lane light_lane(double end, double stop, const TrafficLightCycle& light) {
  Lane lane = straight_lane(1, {0.0, 0.0}, {end, 0.0}, 3.5);
  lane.traffic_lights = {light};
  lane.stop_s = stop;
  return lane;
}

}  // namespace

TEST_CASE("traffic light colour: the CommonRoad cycle with its time offset, as commonroad-io reads it") {
  // USA_Peach-4_8's light 43920 (time step 0.1 s): green 400, yellow 30, red
  // 570 steps, offset 590; the scenario starts in yellow and turns red at 2 s.
  const std::vector<std::pair<std::string, long>> steps{{"green", 400}, {"yellow", 30}, {"red", 570}};
  TrafficLightCycle light;
  for (const auto& [c, d] : steps) light.cycle.push_back({c, static_cast<double>(d) * 0.1});
  light.time_offset = 590 * 0.1;
  for (long k = -1500; k <= 3000; k += 7) {
    CHECK_MESSAGE(light_color(light, static_cast<double>(k) * 0.1) == commonroad_color(steps, 590, k), k);
  }
  CHECK(light_color(light, 0.0) == "yellow");
  CHECK(light_color(light, 1.95) == "yellow");
  CHECK(light_color(light, 2.0) == "red");
  CHECK(light_color(light, 59.0) == "green");
  CHECK(is_stop_color("red"));
  CHECK(is_stop_color("yellow"));
  CHECK(is_stop_color("redYellow"));
  CHECK_FALSE(is_stop_color("green"));
  CHECK_FALSE(is_stop_color("inactive"));
}

TEST_CASE("lane prediction: a car stops at a red light's line, evenly, and goes on when it turns green") {
  // Red for 20 s from t = 0. A car whose front is 40 m before the line (its
  // box centre 2 m behind the front) at 10 m/s: even braking over 39.5 m (the
  // 0.5 m gap) needs 1.27 m/s^2, and it stands from 7.9 s on.
  TrafficLightCycle light;
  light.cycle = {{"red", 20.0}, {"green", 30.0}};
  const std::vector<Lane> lanes{light_lane(200.0, 60.0, light)};
  const LaneMap map(lanes);
  const double front = 2.0;
  const Pose car{18.0, 0.0, 0.0};  // front at 20 m: 40 m before the line
  const std::vector<double> t = times(10.0, 0.1);
  const auto pred = predict_along_lanes(map, car, 10.0, t, 0.0, front);
  REQUIRE(pred.has_value());
  const double room = 40.0 - kStopLineGap;
  const double decel = 10.0 * 10.0 / (2.0 * room);  // independent: v^2 / (2 d)
  const double t_stop = 10.0 / decel;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double tt = std::min(t[k], t_stop);
    const double expected = 18.0 + 10.0 * tt - 0.5 * decel * tt * tt;
    CHECK((*pred)[k].x == doctest::Approx(expected).epsilon(1e-9));
    CHECK((*pred)[k].x + front <= 60.0 - kStopLineGap + 1e-9);  // never past the line
  }
  // Without the light: straight through at 10 m/s.
  std::vector<Lane> plain = lanes;
  plain[0].traffic_lights.clear();
  const auto through = predict_along_lanes(LaneMap(plain), car, 10.0, t, 0.0, front);
  REQUIRE(through.has_value());
  CHECK(through->back().x == doctest::Approx(118.0));

  // Green from 8 s on (red 8 s, green after): it stands from t_stop until
  // then, then accelerates at kGreenStartAccel.
  TrafficLightCycle soon;
  soon.cycle = {{"red", 8.0}, {"green", 30.0}};
  const std::vector<Lane> soon_lanes{light_lane(200.0, 60.0, soon)};
  const std::vector<double> t12 = times(12.0, 0.1);
  const auto go = predict_along_lanes(LaneMap(soon_lanes), car, 10.0, t12, 0.0, front);
  REQUIRE(go.has_value());
  REQUIRE(t_stop < 8.0);
  for (std::size_t k = 0; k < t12.size(); ++k) {
    if (t12[k] > t_stop + 1e-9 && t12[k] <= 8.0 - 0.05) CHECK((*go)[k].x == doctest::Approx(18.0 + room));
    if (t12[k] > 8.1) CHECK((*go)[k].x > 18.0 + room);
  }
  const double g = 12.0 - 8.0;  // at most 0.05 s later (the light is looked up every 0.05 s)
  CHECK(go->back().x <= 18.0 + room + 0.5 * kGreenStartAccel * g * g + 1e-6);
  CHECK(go->back().x >= 18.0 + room + 0.5 * kGreenStartAccel * (g - 0.05) * (g - 0.05) - 1e-6);
}

TEST_CASE("lane prediction: through a green light, through a yellow it cannot stop for, and the time it arrives counts") {
  const std::vector<double> t = times(6.0, 0.1);
  const double front = 2.0;
  const Pose car{18.0, 0.0, 0.0};  // front 40 m before the line at 60 m
  auto last_x = [&](const TrafficLightCycle& light, double v, double now) {
    const std::vector<Lane> lanes{light_lane(300.0, 60.0, light)};
    const auto p = predict_along_lanes(LaneMap(lanes), car, v, t, now, front);
    REQUIRE(p.has_value());
    return p->back().x;
  };
  TrafficLightCycle green;
  green.cycle = {{"green", 100.0}};
  CHECK(last_x(green, 10.0, 0.0) == doctest::Approx(78.0));
  // Yellow when it gets there: it may enter, and drives on.
  TrafficLightCycle yellow;
  yellow.cycle = {{"yellow", 100.0}};
  CHECK(last_x(yellow, 10.0, 0.0) == doctest::Approx(78.0));
  // Red when it gets there, but stopping in 39.5 m from 17 m/s needs
  // 3.66 m/s^2 > 3.05: it drives on; from 15 m/s 2.85 m/s^2: it stops.
  TrafficLightCycle yellow_red;
  yellow_red.cycle = {{"yellow", 2.0}, {"red", 100.0}};
  CHECK(last_x(yellow_red, 17.0, 0.0) == doctest::Approx(18.0 + 17.0 * 6.0));
  CHECK(last_x(yellow_red, 15.0, 0.0) < 60.0);
  // Red already (now = 3 s): up to 5 m/s^2 (19.9 m/s over 39.5 m needs 5.01).
  CHECK(last_x(yellow_red, 17.0, 3.0) < 60.0);
  CHECK(last_x(yellow_red, 19.8, 3.0) < 60.0);
  CHECK(last_x(yellow_red, 19.9, 3.0) == doctest::Approx(18.0 + 19.9 * 6.0));
  // Green now, red when it gets there (4 s at 10 m/s): it stops. Red now,
  // green before it gets there: it drives on.
  TrafficLightCycle turning_red;
  turning_red.cycle = {{"green", 3.0}, {"red", 50.0}};
  CHECK(last_x(turning_red, 10.0, 0.0) < 60.0);
  TrafficLightCycle turning_green;
  turning_green.cycle = {{"red", 3.0}, {"green", 50.0}};
  CHECK(last_x(turning_green, 10.0, 0.0) == doctest::Approx(78.0));
  // The scene time shifts the cycle (53 s long): from now = 50 s it arrives
  // 0.95 s into the next cycle, green for the first, red for the second.
  CHECK(last_x(turning_red, 10.0, 50.0) == doctest::Approx(78.0));
  CHECK(last_x(turning_green, 10.0, 50.0) < 60.0);
}

TEST_CASE("scene/1 extension lanes: traffic lights written and read back, malformed ones are errors") {
  World w = generate_scene(1, 0);
  w.lanes = circle_lanes();
  TrafficLightCycle light;
  light.cycle = {{"green", 40.0}, {"yellow", 3.0}, {"red", 57.0}};
  light.time_offset = 59.0;
  w.lanes[1].traffic_lights = {light};
  w.lanes[1].stop_s = 12.5;
  const SceneParseResult back = parse_scene_text(scene_to_text(w));
  REQUIRE_MESSAGE(back.world.has_value(), back.error);
  CHECK(back.world->lanes[0].traffic_lights.empty());
  REQUIRE(back.world->lanes[1].traffic_lights.size() == 1);
  CHECK(back.world->lanes[1].stop_s == 12.5);
  CHECK(back.world->lanes[1].traffic_lights[0].time_offset == 59.0);
  REQUIRE(back.world->lanes[1].traffic_lights[0].cycle.size() == 3);
  CHECK(back.world->lanes[1].traffic_lights[0].cycle[2].color == "red");
  CHECK(back.world->lanes[1].traffic_lights[0].cycle[2].duration == 57.0);
  std::string text = scene_to_text(w);
  const std::size_t at = text.find("\"duration\"", text.find("\"traffic_lights\""));
  REQUIRE(at != std::string::npos);
  text.replace(at, 10, "\"length\"");
  const SceneParseResult bad = parse_scene_text(text);
  CHECK_FALSE(bad.world.has_value());
  CHECK(bad.error.find("lanes[1].traffic_lights[0]") != std::string::npos);
}
