#pragma once
// The envelope the decision, path and speed stages plan within: the vehicle's
// limits (scene::VehicleLimits; the planner narrows acceleration to its
// comfort setting) and the road's speed limit.
#include <cmath>

#include "itp/config.hpp"
#include "itp/scene/vehicle.hpp"

namespace itp::decision {

struct MotionLimits : scene::VehicleLimits {
  Scalar speed_limit = Scalar(16.7);  // [m/s] road speed limit
};

// The speed limit on a path of curvature `kappa`: the road's limit, and the
// speed at which the lateral acceleration v^2 |kappa| reaches lat_acc_max.
inline Scalar curve_speed_limit(const MotionLimits& lim, Scalar kappa) {
  constexpr Scalar kKappaFloor = Scalar(1e-4);  // [1/m] straighter: only the road's limit
  const Scalar k = std::fabs(kappa);
  if (k <= kKappaFloor) {
    return lim.speed_limit;
  }
  const Scalar v = std::sqrt(lim.lat_acc_max / k);
  return v < lim.speed_limit ? v : lim.speed_limit;
}

}  // namespace itp::decision
