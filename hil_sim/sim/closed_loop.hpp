#pragma once
// The closed loop: a World driven cycle by cycle through any PlannerEndpoint
// (inproc, host, qemu). Every 0.1 s the ego's current simulated state and the
// obstacles' perceived state become a planner Scene; the returned plan is
// tracked by the vehicle model for 0.1 s in 10 ms substeps while the obstacles
// move along their ground truth; SceneMetrics sees the true footprints.
// `hil_sim run` (apps/run_command) runs suites of worlds through it;
// sim/scene_plots, sim/summary_table and sim/cycle_trace present the results.
// docs/simulation.md.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "itp/core/status.hpp"
#include "itp/planner/plan.hpp"
#include "itp/scene/scene.hpp"
#include "sim/metrics.hpp"
#include "sim/planner_endpoint.hpp"
#include "sim/scene_convert.hpp"
#include "sim/sim_config.hpp"
#include "sim/svg.hpp"
#include "sim/vehicle_model.hpp"
#include "sim/world.hpp"

namespace hil::sim {

struct RunOptions {
  Prediction prediction = Prediction::kConstantVelocity;
  double duration = -1.0;        // [s] <= 0: the world's duration, else 12 s
  double cycle = 0.1;            // [s] planning period (also the metrics step)
  // [m/s^2] braking on an invalid_input plan or a link error with no plan to
  // follow; with one, the ego follows the last valid plan, its speed capped
  // so that braking at this rate stops it by the plan's end.
  double emergency_decel = 4.0;
  TrackingGains gains{};
  // Keep copies of the planner Scenes of the most interesting cycle (and the
  // one before it, for stitching) so that plots can re-plan it.
  bool keep_snapshot = false;
};

// One planning cycle as the loop saw it (the state is the one planned from).
struct CycleRecord {
  double t = 0.0;                  // [s] scene time of the cycle
  std::optional<itp::PlanStatus> status;  // nullopt: the endpoint gave no plan (link error)
  std::string reason;              // fallback / invalid_input reason, or the link error
  int iterations = 0;
  double cycle_time_us = -1.0;     // < 0: not measured
  double instructions = -1.0;      // < 0: not measured
  // The planner's stage timing [its ticks] and work counts (itp::planner::StageTiming),
  // written to the trace as "work" (tools/wcet_table.py reads them).
  std::optional<itp::planner::StageTiming> work;
  double v = 0.0;                  // [m/s] ego speed at t
  double v_plan = 0.0;             // [m/s] the plan's speed 1 s ahead (0 when no plan)
  double a_lon = 0.0;              // [m/s^2]
  double a_lat = 0.0;              // [m/s^2]
  std::optional<double> clearance; // [m] min true distance to an obstacle at t
  bool collision = false;          // an overlap at t
  double path_deviation = -1.0;    // [m] this plan's path vs the previous plan's (< 0: none)
  double path_deviation_t = 0.0;   // [s] plan time of that largest deviation
  std::string decisions;           // per obstacle "id:lateral/longitudinal", e.g. "3:L/ignore 7:-/follow"
  std::string collision_with;      // fallback: collision: "obstacle@plan time", e.g. "14@2.3s"
  int left_out = 0;                // obstacles in range the scene could not hold (least relevant first)
  double reference_deviation_m = 0.0;  // resampling of the road window to the capacities
  double boundary_narrowing_m = 0.0;   // (ConvertResult)
  std::optional<long> stop_wall_lane;  // the ego's red light's lane, when its stop wall was sent (ConvertResult)
};

// A cycle worth a look (RunOptions::keep_snapshot): the first fallback /
// invalid input / link error, and the last plan before the first collision
// (else the plan before the step with the smallest clearance).
struct CycleSnapshot {
  int cycle = -1;
  double now = 0.0;          // [s]
  std::string why;           // "collision", "fallback: blocked", "min clearance 0.53 m", ...
  // Scenes to replay in order (the previous cycle's first, when there was
  // one), all of the configuration the run planned with.
  std::vector<std::pair<double, AnySceneRef>> scenes;
};

struct SceneRunResult {
  SceneSummary summary;
  std::vector<svg::EgoTraceSample> trace;  // every step, t = 0 .. duration
  std::vector<CycleRecord> cycles;
  std::vector<CycleSnapshot> snapshots;    // with RunOptions::keep_snapshot, in cycle order
  std::string error;                       // why the scene stopped early ("" = it ran to the end)
};

// Runs one world for its duration. The endpoint is reset() first. Never
// throws: an exception from the endpoint or a world the planner cannot be
// given at all (no reference line) ends the scene as crashed (summary.crashed,
// error). Capacity does not: the scene keeps the most relevant obstacles and
// the cycle counts the others (CycleRecord::left_out). The world becomes
// Scenes of the endpoint's configuration (up to its capacities; the rest is
// left out and counted). Compiled for HIL_SIM_FOR_EACH_CONFIG.
template <class Cfg>
SceneRunResult run_scene(const World& world, BasicPlannerEndpoint<Cfg>& endpoint, const RunOptions& options);

}  // namespace hil::sim
