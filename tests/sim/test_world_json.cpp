// scene/1 reading and writing; pose_at semantics.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include <nlohmann/json.hpp>

#include "sim/scene_generator.hpp"
#include "sim/world.hpp"

using namespace hil::sim;

namespace {
// The example of FORMATS.md, verbatim.
const char* kExample = R"({
  "format": "scene/1",
  "name": "paper-0042",
  "reference_line": [[0.0, 0.0], [5.0, 0.0], [10.0, 0.1]],
  "road": {
    "lane_width": 3.5,
    "left_boundary": 5.25,
    "right_boundary": -1.75,
    "target_lane_offset": 0.0,
    "speed_limit": 16.7
  },
  "ego": {"x": 0.0, "y": 0.0, "heading": 0.0, "v": 10.0, "a": 0.0, "kappa": 0.0,
          "length": 4.8, "width": 1.9, "wheelbase": 2.8},
  "static_obstacles": [
    {"id": 1, "x": 40.0, "y": 0.3, "heading": 0.0, "length": 4.5, "width": 1.8}
  ],
  "dynamic_obstacles": [
    {"id": 11, "length": 4.5, "width": 1.8,
     "trajectory": [{"t": 0.0, "x": 20.0, "y": 3.5, "heading": 0.0, "v": 8.0},
                    {"t": 0.1, "x": 20.8, "y": 3.5, "heading": 0.0, "v": 8.0}]}
  ],
  "duration": 20.0
})";
}  // namespace

TEST_CASE("scene/1: the FORMATS.md example reads with every field") {
  const SceneParseResult r = parse_scene_text(kExample);
  REQUIRE_MESSAGE(r, r.error);
  const World& w = *r.world;
  CHECK(w.name == "paper-0042");
  REQUIRE(w.reference_line.size() == 3);
  CHECK(w.reference_line[2].y == doctest::Approx(0.1));
  CHECK(w.road.left_boundary.is_constant());
  CHECK(w.road.left_boundary.at(100.0) == doctest::Approx(5.25));
  CHECK(w.road.right_boundary.at(0.0) == doctest::Approx(-1.75));
  CHECK(w.road.speed_limit == doctest::Approx(16.7));
  CHECK(w.ego.wheelbase == doctest::Approx(2.8));
  REQUIRE(w.static_obstacles.size() == 1);
  CHECK(w.static_obstacles[0].y == doctest::Approx(0.3));
  REQUIRE(w.dynamic_obstacles.size() == 1);
  CHECK(w.dynamic_obstacles[0].id == 11);
  CHECK(w.dynamic_obstacles[0].trajectory[1].x == doctest::Approx(20.8));
  REQUIRE(w.duration.has_value());
  CHECK(*w.duration == doctest::Approx(20.0));
  CHECK(w.tags.empty());
}

TEST_CASE("scene/1: round trip is exact (example, [s, l] boundaries, generated scenes)") {
  World w = *parse_scene_text(kExample).world;
  w.road.left_boundary.knots = {{0.0, 5.25}, {50.0, 5.0}, {120.0, 1.75}};
  w.duration.reset();
  const std::string t1 = scene_to_text(w);
  const SceneParseResult r = parse_scene_text(t1);
  REQUIRE_MESSAGE(r, r.error);
  CHECK(scene_to_text(*r.world) == t1);
  CHECK(r.world->road.left_boundary.at(85.0) == doctest::Approx(3.375));
  CHECK(r.world->road.left_boundary.at(500.0) == doctest::Approx(1.75));
  CHECK_FALSE(r.world->duration.has_value());
  const nlohmann::json j = nlohmann::json::parse(t1);
  CHECK(j.at("road").at("left_boundary").is_array());
  CHECK_FALSE(j.contains("duration"));
  CHECK_FALSE(j.contains("tags"));

  for (int i = 0; i < 10; ++i) {
    const World g = generate_scene(99, i);
    const std::string a = scene_to_text(g);
    const SceneParseResult back = parse_scene_text(a);
    REQUIRE_MESSAGE(back, back.error);
    CHECK(scene_to_text(*back.world) == a);
    CHECK(back.world->tags == g.tags);
    CHECK(back.world->dynamic_obstacles.front().kind == g.dynamic_obstacles.front().kind);
  }
}

TEST_CASE("scene/1: malformed input is rejected with a clear message, never thrown") {
  nlohmann::json j = nlohmann::json::parse(kExample);
  j["format"] = "scene/2";
  SceneParseResult r = parse_scene(j);
  CHECK_FALSE(r);
  CHECK(r.error.find("expected \"scene/1\"") != std::string::npos);

  j = nlohmann::json::parse(kExample);
  j.erase("format");
  CHECK(parse_scene(j).error.find("format") != std::string::npos);

  j = nlohmann::json::parse(kExample);
  j["dynamic_obstacles"][0]["trajectory"][1]["t"] = 0.0;
  r = parse_scene(j);
  CHECK_FALSE(r);
  CHECK(r.error.find("strictly ascending") != std::string::npos);

  j = nlohmann::json::parse(kExample);
  j["ego"].erase("wheelbase");
  CHECK(parse_scene(j).error.find("wheelbase") != std::string::npos);

  j = nlohmann::json::parse(kExample);
  j["reference_line"] = {{0.0, 0.0}};
  CHECK_FALSE(parse_scene(j));

  j = nlohmann::json::parse(kExample);
  j["road"]["right_boundary"] = "wide";
  CHECK_FALSE(parse_scene(j));

  CHECK_FALSE(parse_scene_text("{ not json"));
  CHECK_FALSE(load_scene_file("/nonexistent/dir/scene.json"));
}

// Issue 13, defect 6: an id beyond the planner's 32 bits was wrapped
// (4294967297 became 1, then a "duplicate" of obstacle 1).
TEST_CASE("scene/1: obstacle ids beyond 32 bits are refused by name, never wrapped") {
  for (const char* text : {R"(4294967297)", R"(2147483648)", R"(-2147483649)", R"(18446744073709551615)"}) {
    for (const char* list : {"static_obstacles", "dynamic_obstacles"}) {
      nlohmann::json j = nlohmann::json::parse(kExample);
      j[list][0]["id"] = nlohmann::json::parse(text);
      const SceneParseResult r = parse_scene(j);
      CHECK_FALSE_MESSAGE(r, list, " id ", text);
      CHECK(r.error.find("\"id\" must be an integer in [-2147483648, 2147483647]") != std::string::npos);
    }
  }
  nlohmann::json j = nlohmann::json::parse(kExample);
  j["static_obstacles"][0]["id"] = 2147483647;
  j["dynamic_obstacles"][0]["id"] = -2147483648LL;
  const SceneParseResult r = parse_scene(j);
  REQUIRE(r);
  CHECK(r.world->static_obstacles[0].id == 2147483647);
  CHECK(r.world->dynamic_obstacles[0].id == -2147483647 - 1);
}

TEST_CASE("pose_at: absent before it appears, interpolates, wraps heading, extrapolates") {
  DynamicObstacle d;
  d.length = 4.5;
  d.width = 1.8;
  d.trajectory = {{1.0, 0.0, 0.0, 3.1, 2.0}, {2.0, 2.0, 4.0, -3.1, 2.0}};
  CHECK_FALSE(pose_at(d, 0.99).has_value());
  REQUIRE(pose_at(d, 1.0).has_value());
  const Pose mid = *pose_at(d, 1.5);
  CHECK(mid.x == doctest::Approx(1.0));
  CHECK(mid.y == doctest::Approx(2.0));
  // Shortest arc from 3.1 to -3.1 passes through pi, not through 0.
  CHECK(std::abs(std::abs(mid.heading) - std::numbers::pi) < 1e-9);
  const Pose after = *pose_at(d, 3.0);  // moves on at v = 2 m/s along heading -3.1
  CHECK(after.x == doctest::Approx(2.0 + 2.0 * std::cos(-3.1)));
  CHECK(after.y == doctest::Approx(4.0 + 2.0 * std::sin(-3.1)));
  CHECK(after.heading == doctest::Approx(-3.1));
}
