// Lane-following predictions on the CommonRoad development scenarios
// (--prediction lane, docs/simulation.md "Predictions"): the import carries
// the lanelet map, and at USA_Peach-4_8 the oncoming car 520, on a curve,
// is predicted along its lane past the standing ego, where constant velocity
// sent it through the ego (every plan a `collision` fallback).
#include <doctest/doctest.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>

#include "itp/configurations.hpp"
#include "sim/box_geometry.hpp"
#include "sim/commonroad_world.hpp"
#include "sim/scene_convert.hpp"

using namespace hil::sim;

namespace {

World import_file(const std::string& name) {
  std::ifstream in(std::string(ITP_COMMONROAD_DATA_DIR) + "/" + name, std::ios::binary);
  REQUIRE_MESSAGE(in.good(), name);
  std::ostringstream ss;
  ss << in.rdbuf();
  const CommonRoadImport r = import_commonroad(ss.str());
  REQUIRE_MESSAGE(r.world.has_value(), r.error);
  return *r.world;
}

// The closest the obstacle's predicted boxes come to the ego standing where it is.
double closest_to_standing_ego(const World& w, Prediction mode, int id) {
  auto scene = std::make_unique<itp::scene::Scene>();
  REQUIRE(make_planner_scene(w, ego_at_start(w), 0.0, mode, *scene).ok);
  const OrientedBox ego = ego_box(w.ego);
  double d = std::numeric_limits<double>::infinity();
  bool found = false;
  for (const auto& o : scene->dynamic_obstacles) {
    if (o.id != id) continue;
    found = true;
    for (const auto& p : o.trajectory) {
      d = std::min(d, box_distance(ego, OrientedBox{p.x, p.y, p.heading, o.length, o.width}));
    }
  }
  REQUIRE_MESSAGE(found, id);
  return d;
}

}  // namespace

TEST_CASE("CommonRoad import: the vehicle lanelets become the world's lane map") {
  const World w = import_file("USA_Peach-4_8_T-1.xml");
  REQUIRE(w.lanes.size() > 20);
  bool ego_lane = false;
  for (const Lane& l : w.lanes) {
    CHECK(l.centre.size() >= 2);
    CHECK(l.left.size() >= 2);
    CHECK(l.right.size() >= 2);
    ego_lane = ego_lane || l.id == 43648;  // the ego's lanelet (docs/commonroad.md)
  }
  CHECK(ego_lane);
}

TEST_CASE("USA_Peach-4_8: the oncoming car 520 on the curve passes the standing ego along its lane, constant velocity runs into it") {
  const World w = import_file("USA_Peach-4_8_T-1.xml");
  // Constant velocity: 520 drifts 3 degrees towards the ego's line and
  // overlaps the standing ego within the horizon.
  CHECK(closest_to_standing_ego(w, Prediction::kConstantVelocity, 520) == 0.0);
  // Along its lane it passes beside the ego, as in the recording (0.97 m).
  const double lane = closest_to_standing_ego(w, Prediction::kLane, 520);
  MESSAGE("520 along its lane: closest ", lane, " m to the standing ego");
  CHECK(lane > 0.8);
  CHECK(closest_to_standing_ego(w, Prediction::kGroundTruth, 520) > 0.8);
}

TEST_CASE("USA_Peach-4_8: the southbound queue stops at red light 43920 in the lane prediction, as in the recording") {
  // Light 43920 (lanelets 43343, 43208, 43349, ending at y = 26.5 - 26.6 m)
  // is yellow from 0 s and red from 2 s. The queue cars 566 and 569 brake
  // for it: by 6 s they stand (below 1 m/s) with their fronts a few metres
  // past the lanelets' end (the recording; NGSIM's stop positions lie past
  // the mapped line). At 2 s, 13 m before the line at 9.7 and 8.6 m/s, both
  // are predicted to stop before it (before the change: on through the
  // intersection at their speed, 50 m and more past it).
  const World w = import_file("USA_Peach-4_8_T-1.xml");
  // The road configuration: every car in range (the default one keeps the 5 most relevant).
  auto scene = std::make_unique<itp::scene::BasicScene<itp::RoadConfig>>();
  REQUIRE(make_planner_scene<itp::RoadConfig>(w, ego_at_start(w), 2.0, Prediction::kLane, *scene).ok);
  constexpr double kLine = 26.6;  // [m] y of the lanelets' end
  int checked = 0;
  for (const auto& o : scene->dynamic_obstacles) {
    if (o.id != 566 && o.id != 569) continue;
    ++checked;
    double lowest_front = std::numeric_limits<double>::infinity();
    for (const auto& p : o.trajectory) lowest_front = std::min(lowest_front, p.y - 0.5 * o.length);  // heading south
    MESSAGE(o.id, ": predicted front lowest at y = ", lowest_front);
    CHECK(lowest_front > kLine - 0.5);  // before the line (its heading slants the front by a few cm)
    CHECK(lowest_front < kLine + 1.5);  // and up to it, not short of it
    // The recording: standing at 6 s, its front past the line by less than 5 m.
    for (const DynamicObstacle& d : w.dynamic_obstacles) {
      if (d.id != o.id) continue;
      const std::optional<Pose> at6 = pose_at(d, 6.0);
      REQUIRE(at6.has_value());
      CHECK(d.trajectory.back().v < 1.0);
      CHECK(at6->y - 0.5 * d.length > kLine - 5.0);
    }
  }
  CHECK(checked == 2);
  // The lanes with the light carry it, its stop line at their end.
  int with_light = 0;
  for (const Lane& l : w.lanes) {
    if (l.id == 43343 || l.id == 43208 || l.id == 43349) {
      ++with_light;
      REQUIRE(l.traffic_lights.size() == 1);
      CHECK(light_color(l.traffic_lights[0], 1.9) == "yellow");
      CHECK(light_color(l.traffic_lights[0], 2.0) == "red");
      CHECK(l.stop_s == doctest::Approx(polyline_arc_lengths(l.centre).back()));
    }
  }
  CHECK(with_light == 3);
}
