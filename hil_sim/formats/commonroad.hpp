#pragma once
// CommonRoad scenarios (XML, 2020a; the 2018b files of the public benchmark
// set too) read into plain structs: what the file says, in its own terms
// (time steps, shapes in the obstacle's frame, lanelet ids), nothing mapped
// yet. The mapping to the simulator's World is sim/commonroad_world.hpp;
// docs/commonroad.md says what is read and what is refused.
//
// read_commonroad() is a plain function text -> scenario or error: it never
// throws and never aborts on malformed input (it is the fuzz target's entry).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hil::formats::commonroad {

// Input limits (docs/commonroad.md, "Input limits"): a file beyond one is refused
// with an error naming the element and the limit. Real scenarios stay far
// below them (the dev set: bounds <= 1 195 m, routes <= 1 093 m, coordinates
// <= 5 939 m); each one bounds what a file built to defeat the importer costs.
namespace limits {
// [m] |x| and |y| of every point (the reader): a projection of any place on
// Earth stays within 4 * 10^7 m (UTM northings reach 10^7). Keeps all geometry
// finite (squared differences < 10^17), whatever the file holds.
inline constexpr double kMaxCoordinate = 1.0e8;
// [m] the length of a lanelet bound, the sum of its segments (the reader):
// at most 10 km / 0.5 m = 2 * 10^4 edge samples per bound.
inline constexpr double kMaxBoundLength = 10000.0;
// [m] the route's reference line (sim/commonroad_route.cpp): the route is
// wanted at most 5 km ahead, but long lanelets and the gaps between
// successors that do not meet add to it; bounds the road edges' knots (one
// per metre, 2 * 10^4 per edge) and so the scene's size.
inline constexpr double kMaxRouteLength = 20000.0;
// [m] the bounds the road is sampled from (sim/commonroad_route.cpp): each
// route lanelet's own two and the outermost ones beside it, every bound
// counted once. Every sample is projected onto the reference line, against
// all of its V points: at most 4 * 10^4 m / 0.5 m = 8 * 10^4 samples, plus
// one per segment of those bounds (P points), so at most (8 * 10^4 + P) * V
// segment tests. A point takes >= 31 bytes of XML, so a 16 KB file (the
// fuzzer's) has P, V < 530: < 4.3 * 10^7 tests, about 1.5 s of CPU in the
// fuzz build (ASan, UBSan). 40 km is a road of four 10 km bounds; a real
// 5 km route with its outer bounds has about 20 km (DEU_A9: 3.3 km).
inline constexpr double kMaxRoadBoundLength = 40000.0;
}  // namespace limits

struct Vec2 {
  double x = 0.0;  // [m]
  double y = 0.0;  // [m]
};

// One primitive of a shape, in the obstacle's local frame (x along its
// orientation): CommonRoad places it by rotating with the state's
// orientation and translating to the state's position.
struct ShapePart {
  enum class Kind { kRectangle, kCircle, kPolygon };
  Kind kind = Kind::kRectangle;
  double length = 0.0;       // [m] rectangle, along its orientation
  double width = 0.0;        // [m] rectangle
  double radius = 0.0;       // [m] circle
  double orientation = 0.0;  // [rad] rectangle, relative to the obstacle
  Vec2 center;               // [m] rectangle / circle centre, local frame
  std::vector<Vec2> points;  // [m] polygon vertices (>= 3), local frame
};
using Shape = std::vector<ShapePart>;  // >= 1 part (a shape group when several)

// A state as the file gives it. Intervals and position regions (uncertain
// states, e.g. in recorded 2018b data) are read as their midpoint / centre;
// `uncertain` says that happened.
struct State {
  long time_step = 0;                 // integer time step (t = time_step * dt)
  Vec2 position;                      // [m] the obstacle's / vehicle's reference point
  double orientation = 0.0;           // [rad]
  std::optional<double> velocity;     // [m/s]
  std::optional<double> acceleration; // [m/s^2]
  std::optional<double> yaw_rate;     // [rad/s]
  bool uncertain = false;
};

struct Obstacle {
  long id = 0;
  bool dynamic = false;
  std::string type;              // "car", "pedestrian", "parkedVehicle", ...
  Shape shape;
  State initial;
  std::vector<State> trajectory;  // after the initial state, ascending time steps
  int line = 0;                   // of the element in the file (for messages)
};

enum class DrivingDirection { kSame, kOpposite };

struct Neighbour {
  long id = 0;
  DrivingDirection direction = DrivingDirection::kSame;
};

struct Lanelet {
  long id = 0;
  std::vector<Vec2> left_bound;   // [m] >= 2 points, driving direction
  std::vector<Vec2> right_bound;  // [m] >= 2 points
  std::vector<long> predecessors;
  std::vector<long> successors;
  std::optional<Neighbour> left;
  std::optional<Neighbour> right;
  std::vector<std::string> types;     // laneletType elements
  std::vector<long> traffic_signs;    // trafficSignRef
  std::vector<long> traffic_lights;   // trafficLightRef (of the lanelet and of its stopLine)
  // <stopLine>: its two points when given (else the stop line is the
  // lanelet's end, CommonRoad 2020a).
  std::vector<Vec2> stop_line;
  std::optional<double> speed_limit;  // [m/s] 2018b <speedLimit>
  int line = 0;
};

// A <trafficLight> (2020a): its cycle repeats; the state at time step k is the
// cycle element holding phase (k - time_offset) mod (sum of the durations),
// counted from the first element (commonroad-io's
// TrafficLight.get_state_at_time_step).
struct TrafficLightPhase {
  std::string color;  // "red", "yellow", "redYellow", "green", "inactive"
  long duration = 0;  // time steps, > 0
};

struct TrafficLight {
  long id = 0;
  std::vector<TrafficLightPhase> cycle;  // >= 1 element
  long time_offset = 0;                  // time steps
  std::string direction = "all";         // all, left, straight, right, leftStraight, ...
  bool active = true;
  int line = 0;
};

struct TrafficSignElement {
  std::string sign_id;              // country-specific, e.g. "274", "R2-1"
  std::vector<std::string> values;  // additionalValue, as written
};

struct TrafficSign {
  long id = 0;
  std::vector<TrafficSignElement> elements;
  std::optional<Vec2> position;
  bool is_virtual = false;
  int line = 0;
};

struct GoalState {
  std::optional<long> time_start;  // time steps
  std::optional<long> time_end;
  std::vector<long> lanelets;      // goal position given as lanelet references
  std::vector<Vec2> area_centres;  // [m] goal position given as shapes: their centres
};

struct PlanningProblem {
  long id = 0;
  State initial;
  std::vector<GoalState> goals;
  int line = 0;
};

struct Scenario {
  std::string benchmark_id;
  std::string version;        // commonRoadVersion, e.g. "2020a"
  double time_step = 0.1;     // [s] timeStepSize
  std::vector<Lanelet> lanelets;
  std::vector<TrafficSign> traffic_signs;
  std::vector<TrafficLight> traffic_lights;
  std::vector<Obstacle> obstacles;  // static and dynamic, file order
  std::vector<PlanningProblem> planning_problems;
  // Content read past on purpose (intersections, environment obstacles, ...), one line each, for the importer's notes.
  std::vector<std::string> ignored;
};

// Options of the reader itself.
struct ReadOptions {
  // Set-based predictions (occupancySet, phantomObstacle) are refused unless
  // this is set; then those obstacles are left out and listed in `ignored`.
  bool drop_set_based = false;
};

struct ReadResult {
  std::optional<Scenario> scenario;  // set on success
  std::string error;                 // "line 12: lanelet 5: leftBound: ..." on failure
  explicit operator bool() const { return scenario.has_value(); }
};

ReadResult read_commonroad(std::string_view xml, const ReadOptions& options = {});

}  // namespace hil::formats::commonroad
