#pragma once
// The check of paper 2 with the real footprints, not the SL boxes: the ego's
// box at every trajectory sample against every static obstacle and every
// dynamic obstacle's motion at that sample's time (as planned against).
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

// `motions[i]` is scene.dynamic_obstacles[i] at the trajectory's sample
// times (the trajectory is sampled at the ST samples).
template <class Cfg>
CollisionHit first_collision(const scene::BasicScene<Cfg>& scene,
                             std::span<const MotionSamples<Cfg>> motions,
                             const BasicPlan<Cfg>& plan);

}  // namespace itp::planner
