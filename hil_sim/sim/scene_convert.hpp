#pragma once
// From the simulator's world to the planner's Scene for one cycle: the
// reference-line window around the ego, the road boundaries shifted into the
// window's arc length, static obstacles, and dynamic obstacles with their
// predictions over the speed horizon (ground truth, or constant velocity and
// heading from their current state, as a perception stack would give).
#include <string>

#include "itp/scene/scene.hpp"
#include "sim/world.hpp"

namespace hil::sim {

enum class Prediction { kGroundTruth, kConstantVelocity };

struct EgoNow {
  double x = 0, y = 0, heading = 0;  // rear axle [m], [rad]
  double v = 0, a = 0, kappa = 0;    // [m/s], [m/s^2], [1/m]
};

EgoNow ego_at_start(const World& world);

struct ConvertResult {
  bool ok = false;
  std::string error;          // capacity or geometry problem, for people
  double window_s0 = 0;       // [m] arc length of the window's first point on the world line
};

// Predictions are sampled every 0.1 s from `now` over the horizon (plus 0.5 s),
// time-stamped in scene time: plan the result with PlanRequest::now = now.
ConvertResult make_planner_scene(const World& world, const EgoNow& ego, double now, Prediction mode,
                                 itp::scene::Scene& out);

}  // namespace hil::sim
