#pragma once
// The fallback of PLANNER.md, "Output and failure": a safe stop. It brakes
// at the comfortable deceleration along the previous plan's path if that plan
// is recent, else along the reference line at the lateral offset held since
// the first fallback cycle, else (no usable reference) straight ahead. When
// comfortable braking runs into an obstacle (collision_check.hpp; a rear-end
// by a follower does not count) it brakes
// at the vehicle's limit, unless that collides sooner (traffic closing in
// from behind): then comfortably after all. A function of its inputs and the
// memory held across consecutive fallbacks; never fails.
#include <span>

#include "itp/geometry/reference_line.hpp"
#include "itp/planner/collision_check.hpp"
#include "itp/planner/plan.hpp"
#include "itp/planner/sl_scene.hpp"
#include "itp/scene/scene.hpp"

namespace itp::planner {

// Held across consecutive fallback cycles (cleared by an ok plan).
struct FallbackMemory {
  bool holding_l = false;
  Scalar l = 0;  // [m] lateral offset of the first fallback cycle
};

template <class Cfg>
struct BasicSafeStopInput {
  const scene::BasicScene<Cfg>* scene = nullptr;  // null: nothing usable arrived
  Scalar now = 0;                                 // [s] scene time of this cycle
  const BasicPlan<Cfg>* previous = nullptr;       // the last ok plan; null: none
  Scalar previous_time = 0;                       // [s] its scene time
  const geometry::BasicReferenceLine<Cfg>* reference = nullptr;  // this cycle's
  std::span<const MotionSamples<Cfg>> motions;    // dynamic obstacles, for the collision check
  EgoLane lane{};                                 // ... and its rear-end rule
  Scalar comfort_decel = Scalar(-3);              // [m/s^2] < 0
};

// Writes the stop into `out`: status fallback with `reason`. An invalid_input
// status already in `out` stays, and then nothing of the scene is used: the
// stop starts from the last valid state (the recent last ok plan at `now`),
// else it is a standstill at the last valid position.
template <class Cfg>
void safe_stop(const BasicSafeStopInput<Cfg>& in, FallbackReason reason, FallbackMemory& memory,
               BasicPlan<Cfg>& out);

}  // namespace itp::planner
