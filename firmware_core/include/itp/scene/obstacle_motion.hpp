#pragma once
// Where a dynamic obstacle is at time t (scene/1 semantics).
#include "itp/scene/scene.hpp"

namespace itp::scene {

struct ObstacleSample {
  bool present = false;        // false before the first sample's t
  Scalar x = Scalar(0);        // [m] box centre
  Scalar y = Scalar(0);        // [m]
  Scalar heading = Scalar(0);  // [rad]
  Scalar v = Scalar(0);        // [m/s]
};

// Pose at time t [s]: absent before the first sample; linear interpolation
// of x, y, v and of heading along the shorter turn between samples; after the
// last sample, straight on at its velocity and heading. Bisection over the
// samples (bounded by kMaxPredictionSamples). Requires a valid obstacle
// (non-empty trajectory with strictly ascending t).
template <class Cfg>
ObstacleSample sample_pose(const BasicDynamicObstacle<Cfg>& obstacle, Scalar t);

}  // namespace itp::scene
