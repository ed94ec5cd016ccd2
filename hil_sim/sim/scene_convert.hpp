#pragma once
// From the simulator's world to the planner's Scene for one cycle: the
// reference-line window around the ego, the road boundaries shifted into the
// window's arc length, static obstacles, and dynamic obstacles with their
// predictions over the speed horizon (ground truth; constant velocity and
// heading from their current state, as a perception stack would give; or
// along their lane at their current speed, sim/lane_prediction.hpp).
//
// The scene arrives as the receiving configuration holds it (docs/commonroad.md,
// "Resampling" and "Obstacle selection"): a window with more reference points
// or boundary knots than Cfg holds is resampled (the reference polyline to a
// subset of its vertices within a measured distance, the boundaries never
// wider than the real road, narrowed by that distance too), and more
// obstacles in range than Cfg holds are cut to the most relevant ones, with a
// count of those left out. Capacity never makes the conversion fail.
#include <cmath>
#include <optional>
#include <string>

#include "itp/scene/scene.hpp"
#include "sim/world.hpp"

namespace hil::sim {

// kLane: along the lane each obstacle is on (World::lanes), constant velocity
// where none matches; a world without lanes (a generated scene) gets exactly
// the constant-velocity predictions.
enum class Prediction { kGroundTruth, kConstantVelocity, kLane };

// "truth", "cv", "lane".
const char* prediction_name(Prediction p);

struct EgoNow {
  double x = 0, y = 0, heading = 0;  // rear axle [m], [rad]
  double v = 0, a = 0, kappa = 0;    // [m/s], [m/s^2], [1/m]
};

EgoNow ego_at_start(const World& world);

struct ConvertResult {
  bool ok = false;
  std::string error;          // a world the planner cannot be given at all (not capacity)
  double window_s0 = 0;       // [m] arc length of the window's first point on the world line
  // Obstacles in range that the scene could not hold (the least relevant).
  int static_left_out = 0;
  int dynamic_left_out = 0;
  // Resampling to the capacities: the reference polyline's Hausdorff distance
  // to the world's, and the largest narrowing of either boundary (including
  // that distance, by which both boundaries are moved inwards).
  double reference_deviation_m = 0.0;
  double boundary_narrowing_m = 0.0;
  // A red (or yellow, stoppable) light on the ego's route put a stop wall into
  // the scene (sim/ego_traffic_lights.hpp): the lane it belongs to.
  std::optional<long> stop_wall_lane;
  int left_out() const { return static_left_out + dynamic_left_out; }
};

// The step of the predictions make_planner_scene sends for Cfg: every 0.1 s,
// or the smallest multiple of it whose samples over the speed horizon plus
// 0.5 s Cfg holds (the default configuration: 0.1 s, 76 samples of its 80;
// the road configuration: 0.2 s, 39 of its 40).
template <class Cfg>
double prediction_step() {
  constexpr double kBase = 0.1;  // [s]
  const double horizon = static_cast<double>(Cfg::kSpeedHorizon) + 0.5;
  double step = kBase;
  while (std::lround(horizon / step) + 1 > Cfg::kMaxPredictionSamples) step += kBase;  // a few turns
  return step;
}

// Predictions are sampled every prediction_step<Cfg>() from `now` over the
// horizon plus 0.5 s, time-stamped in scene time: plan the result with
// PlanRequest::now = now. Compiled for every configuration of ITP_FOR_EACH_CONFIG.
template <class Cfg>
ConvertResult make_planner_scene(const World& world, const EgoNow& ego, double now, Prediction mode,
                                 itp::scene::BasicScene<Cfg>& out);

// The relevance rule that decides which obstacles a full scene keeps: the
// smallest distance between the obstacle's footprint (as sent: its
// prediction, sampled every 0.5 s over the speed horizon) and the ego's
// footprint moving along its lane (the reference line, at its current lateral
// offset) either at its current speed or braking at 4 m/s^2 to a stop (so the
// traffic close behind counts too). Smaller is more relevant; ties go to the
// obstacle ahead of the ego, then to the nearer one now, then to the lower id.
struct Relevance {
  double approach_m = 0.0;  // [m] nearest predicted approach to the ego
  bool ahead = true;        // its centre is ahead of the ego's rear axle now
  double distance_now_m = 0.0;
  int id = 0;
  bool operator<(const Relevance& o) const;
};

}  // namespace hil::sim
