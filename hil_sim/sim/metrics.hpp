#pragma once
// Closed-loop metrics: a per-scene accumulator fed every simulation step, a
// suite aggregator, and the report/1 writer. Definitions: docs/simulation.md.
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "itp/core/status.hpp"
#include "sim/box_geometry.hpp"
#include "sim/vehicle_model.hpp"
#include "sim/world.hpp"

namespace hil::sim {

// Smallest signed distance of the box's corners inside the drivable area
// (min over corners of min(left(s) - l, l - right(s))); negative when a
// corner is beyond a boundary.
double road_margin(std::span<const Point2> reference_line, const Road& road, const OrientedBox& box);

// What the simulator knows after one step (0.1 s).
struct StepSample {
  double t = 0.0;                         // [s]
  OrientedBox ego;                        // true footprint
  Point2 ego_velocity;                    // [m/s] world frame
  std::vector<OrientedBox> obstacles;     // true footprints of the obstacles present
  std::vector<Point2> obstacle_velocities;  // [m/s] per obstacle (empty: all standing)
  double progress_s = 0.0;                // [m] ego's s along the reference line
  double lateral_offset = 0.0;            // [m] ego's l (rear axle)
  double heading_error = 0.0;             // [rad] ego heading - reference heading
  double road_margin = 0.0;               // [m] see road_margin()
  double a_lon = 0.0;                     // [m/s^2]
  double a_lat = 0.0;                     // [m/s^2] v^2 kappa
  // The planning cycle of this step (nullopt: no plan this step: none was
  // requested, or the link gave none).
  std::optional<itp::PlanStatus> status;
  std::string reason;                     // fallback / invalid_input reason
  std::optional<int> iterations;
  std::optional<double> cycle_time_us;    // host targets
  std::optional<double> instructions;     // qemu (-icount shift=0)
};

struct SceneSummary {
  std::string name;
  int steps = 0;
  int cycles = 0;                       // steps with a status (a plan came back)
  int collision_steps = 0;              // steps with any ego/obstacle overlap
  // The first collision: the ego ran into the obstacle, or was hit by it.
  // Of the closing speed along the line between the two centres (ego to
  // obstacle), the ego's share v_ego . n and the obstacle's -v_obs . n; the
  // larger share is the one that ran into the other (a tie: the ego).
  enum class CollisionKind { kNone, kRanInto, kHit };
  CollisionKind collision_kind = CollisionKind::kNone;
  std::optional<double> min_clearance_m;  // nullopt: no obstacle was ever present
  int road_departure_steps = 0;         // steps with road_margin < 0
  double max_road_excess_m = 0.0;       // max(-road_margin, 0)
  int fallbacks = 0;
  std::map<std::string, int> fallback_reasons;
  int invalid_inputs = 0;
  std::map<std::string, int> invalid_input_reasons;
  int link_errors = 0;                  // cycles without a fresh plan (no valid reply in time)
  int corrupt_scenes_accepted = 0;      // plans of a Scene other than the one sent (CRC echo differs)
  // Obstacles in range that the receiving configuration could not hold (the
  // conversion kept the most relevant ones): cycles where any were left out,
  // their sum over cycles, the most in one cycle.
  int left_out_cycles = 0;
  int left_out_total = 0;
  int left_out_max = 0;
  bool crashed = false;
  std::string crash_reason;
  double progress_m = 0.0;              // last s - first s
  double max_abs_lon_acc = 0.0;
  double max_abs_lat_acc = 0.0;
  double max_abs_jerk = 0.0;            // [m/s^3] from consecutive a_lon
  double max_abs_lateral_offset = 0.0;
  double max_abs_heading_error = 0.0;
  std::optional<double> max_plan_deviation_m;  // consecutive plans, lateral, common times
  std::optional<double> max_path_deviation_m;  // consecutive plans, distance between their paths (geometry only)
  std::vector<int> iterations;
  std::vector<double> cycle_time_us;
  std::vector<double> instructions;
  std::vector<std::string> tags;

  bool collided() const { return collision_steps > 0; }
  bool departed() const { return road_departure_steps > 0; }
};

// The kind of a contact between the ego and an obstacle moving at the given
// velocities (SceneSummary::collision_kind).
SceneSummary::CollisionKind who_ran_into(const OrientedBox& ego, Point2 v_ego, const OrientedBox& obstacle,
                                          Point2 v_obstacle);
const char* collision_kind_name(SceneSummary::CollisionKind kind);

class SceneMetrics {
 public:
  explicit SceneMetrics(std::string name, std::vector<std::string> tags = {});
  void add_step(const StepSample& sample);
  // Every accepted plan (absolute start time, its trajectory with t from 0):
  // feeds plan consistency.
  // Returns this plan's path deviation from the previous one [m] (-1: none to compare).
  double add_plan(double t_start, std::span<const TrajectoryPoint> plan);
  // Where that deviation is largest: the new plan's sample time [s from its start].
  double last_path_deviation_time() const { return last_dev_t_; }
  void add_link_error(int count = 1);
  void add_corrupt_scene() { ++s_.corrupt_scenes_accepted; }
  // Obstacles the cycle's scene could not hold (0: none).
  void add_left_out(int count);
  void set_crashed(std::string reason);
  const SceneSummary& summary() const { return s_; }

 private:
  SceneSummary s_;
  std::optional<double> first_s_;
  std::optional<double> last_a_lon_;
  double last_t_ = 0.0;
  std::vector<TrajectoryPoint> prev_plan_;
  double prev_start_ = 0.0;
  double last_dev_t_ = 0.0;
};

struct Stats {
  std::optional<double> median, p99, max, mean;
};
// median: mean of the two middle values for even n; p99: nearest rank
// (sorted[ceil(0.99 n) - 1]); all nullopt for no samples.
Stats compute_stats(std::vector<double> samples);

class SuiteAggregator {
 public:
  void add(SceneSummary scene);
  const std::vector<SceneSummary>& scenes() const { return scenes_; }
  // report/1 with every required key (null where nothing was measured).
  nlohmann::json report(const std::string& target) const;

 private:
  std::vector<SceneSummary> scenes_;
};

nlohmann::json scene_summary_json(const SceneSummary& s);
// Writes the report as pretty JSON; returns "" or an error message.
std::string write_report(const nlohmann::json& report, const std::string& path);

}  // namespace hil::sim
