#pragma once
// The check of paper 2 with the real footprints, not the SL boxes: the ego's
// box at every trajectory sample against every static obstacle and every
// dynamic obstacle's motion at that sample's time (as planned against).
//
// RSS's rule for the car behind (Shalev-Shwartz et al. 2017): it keeps the
// safe distance to the car ahead whatever that car does short of braking
// beyond b_max, and is responsible for a rear-end collision. A predicted hit
// is such a one when the mover comes along the ego's way (heading within
// 45 deg) from behind (its centre behind the ego's rear bumper), faster than
// the ego (its speed from its motion over the last step), and the ego kept
// to its target lane from the plan's start to the hit (it did not cut in
// ahead of it). No plan of the ego removes such a hit without braking less
// for what lies ahead or leaving its lane in front of other traffic, so it
// does not make the plan unsafe; once a rear-end, the same overlap later on
// is the same rear-end.
#include <cstdint>
#include <span>

#include "itp/planner/plan.hpp"
#include "itp/planner/sl_scene.hpp"
#include "itp/scene/scene.hpp"

namespace itp::planner {

struct CollisionHit {
  int sample = -1;              // first trajectory sample that overlaps; -1: none
  std::int32_t obstacle = -1;   // the obstacle it overlaps
  bool found() const { return sample >= 0; }
};

// The ego's lane, for the rear-end rule; lane_width <= 0: every hit counts.
struct EgoLane {
  Scalar target_offset = 0;  // [m] l of the target lane's centre
  Scalar lane_width = 0;     // [m]
};

// `motions[i]` is scene.dynamic_obstacles[i] at the trajectory's sample
// times (the trajectory is sampled at the ST samples).
template <class Cfg>
CollisionHit first_collision(const scene::BasicScene<Cfg>& scene,
                             std::span<const MotionSamples<Cfg>> motions, const BasicPlan<Cfg>& plan,
                             const EgoLane& lane = {});

}  // namespace itp::planner
