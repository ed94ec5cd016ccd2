#pragma once
// Host-side plain structs for a scene/1 world (see /work/shared/design/FORMATS.md
// and docs/simulation.md) and their JSON mapping. Units are SI, angles CCW from +x.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace hil::sim {

struct Point2 {
  double x = 0.0;  // [m]
  double y = 0.0;  // [m]
};

struct Pose {
  double x = 0.0;        // [m]
  double y = 0.0;        // [m]
  double heading = 0.0;  // [rad]
};

// One of road.left_boundary / road.right_boundary: a constant l, or a piecewise
// linear l(s) given as [s, l] pairs (held constant beyond the first/last pair).
struct Boundary {
  struct Knot {
    double s = 0.0;  // [m] arc length along the reference line
    double l = 0.0;  // [m] lateral offset, left positive
  };
  double constant = 0.0;     // [m] used when knots is empty
  std::vector<Knot> knots;   // strictly ascending s when not empty

  static Boundary constant_at(double l) { return Boundary{l, {}}; }
  bool is_constant() const { return knots.empty(); }
  double at(double s) const;  // [m]
};

struct Road {
  double lane_width = 3.5;          // [m]
  Boundary left_boundary;           // l of the drivable area's left edge
  Boundary right_boundary;          // l of the drivable area's right edge
  double target_lane_offset = 0.0;  // [m] l of the target lane's centre
  double speed_limit = 0.0;         // [m/s]
};

struct Ego {
  double x = 0.0;          // [m] rear-axle centre
  double y = 0.0;          // [m]
  double heading = 0.0;    // [rad]
  double v = 0.0;          // [m/s]
  double a = 0.0;          // [m/s^2]
  double kappa = 0.0;      // [1/m]
  double length = 4.8;     // [m]
  double width = 1.9;      // [m]
  double wheelbase = 2.8;  // [m]
};

struct StaticObstacle {
  int id = 0;
  double x = 0.0;        // [m] box centre
  double y = 0.0;        // [m]
  double heading = 0.0;  // [rad]
  double length = 0.0;   // [m]
  double width = 0.0;    // [m]
  std::string kind;      // optional extension "kind" (archetype), "" = absent
};

struct TimedPose {
  double t = 0.0;        // [s] from the scene's start
  double x = 0.0;        // [m] box centre
  double y = 0.0;        // [m]
  double heading = 0.0;  // [rad]
  double v = 0.0;        // [m/s] speed along heading
};

struct DynamicObstacle {
  int id = 0;
  double length = 0.0;               // [m]
  double width = 0.0;                // [m]
  std::vector<TimedPose> trajectory;  // strictly ascending t, >= 1 sample
  std::string kind;                  // optional extension "kind" (archetype)
};

// One lane of the optional extension "lanes" (the CommonRoad import writes its
// vehicle lanelets): the map the lane-following prediction moves obstacles
// along (docs/simulation.md, "Predictions"). Other readers may ignore it.
// A traffic light's fixed cycle (CommonRoad 2020a <trafficLight>): at time t
// it shows the phase that holds (t - time_offset) mod (the durations' sum),
// counted from the first phase.
struct LightPhase {
  std::string color;      // "red", "yellow", "redYellow", "green", "inactive"
  double duration = 0.0;  // [s] > 0
};
struct TrafficLightCycle {
  std::vector<LightPhase> cycle;  // >= 1 phase
  double time_offset = 0.0;       // [s]
};

// The colour `light` shows at scene time t [s].
const std::string& light_color(const TrafficLightCycle& light, double t);
// Whether a colour tells traffic to stop before the line: red, yellow,
// redYellow (not green, not inactive).
bool is_stop_color(const std::string& color);

struct Lane {
  long id = 0;
  std::vector<Point2> centre;  // [m] centre line, driving direction, >= 2 points
  std::vector<Point2> left;    // [m] left bound, driving direction, >= 2 points
  std::vector<Point2> right;   // [m] right bound, driving direction, >= 2 points
  std::vector<long> successors;
  // The lane's traffic lights (optional): traffic stops before `stop_s`
  // (arc length along `centre`) while every one of them shows a stop colour.
  std::vector<TrafficLightCycle> traffic_lights;
  double stop_s = 0.0;  // [m] meaningful with traffic_lights
};

struct World {
  std::string name;
  std::vector<Point2> reference_line;  // centre of the ego's lane, driving order, >= 2 points
  Road road;
  Ego ego;
  std::vector<StaticObstacle> static_obstacles;
  std::vector<DynamicObstacle> dynamic_obstacles;
  std::optional<double> duration;  // [s] closed-loop run length
  std::vector<std::string> tags;   // optional extension "tags" (generator archetypes)
  std::vector<Lane> lanes;         // optional extension "lanes" (CommonRoad: the lanelet map)
};

// The pose of a dynamic obstacle at time t: nullopt before its first sample;
// linear interpolation of x, y and shortest-arc heading between samples;
// after the last sample it moves on at its last speed and heading.
std::optional<Pose> pose_at(const DynamicObstacle& obstacle, double t);

// Heading wrapped to (-pi, pi].
double wrap_angle(double a);

// nlohmann mapping. from_json throws nlohmann::json::exception / std::runtime_error
// on malformed input (wrong "format", missing keys, non-ascending t, ...);
// use parse_scene() for an exception-free loader.
void to_json(nlohmann::json& j, const World& w);
void from_json(const nlohmann::json& j, World& w);

struct SceneParseResult {
  std::optional<World> world;  // set on success
  std::string error;           // set on failure, human readable
  explicit operator bool() const { return world.has_value(); }
};

SceneParseResult parse_scene(const nlohmann::json& j);
SceneParseResult parse_scene_text(const std::string& text);
SceneParseResult load_scene_file(const std::string& path);

// Pretty-printed scene/1 text (indent 1 keeps 0.1 s trajectories readable).
std::string scene_to_text(const World& w, int indent = 1);
// Writes scene_to_text() to path; returns an error message or "" on success.
std::string save_scene_file(const World& w, const std::string& path);

}  // namespace hil::sim
