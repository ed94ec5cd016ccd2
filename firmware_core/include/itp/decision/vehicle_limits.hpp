#pragma once
// Dynamic limits the decision, path and speed stages respect.
#include <cmath>

#include "itp/config.hpp"

namespace itp::decision {

struct VehicleLimits {
  Scalar speed_limit = Scalar(16.7);  // [m/s] road speed limit
  Scalar a_max = Scalar(2.0);         // [m/s^2] comfortable acceleration
  Scalar a_min = Scalar(-4.0);        // [m/s^2] braking limit (negative)
  Scalar a_lat_max = Scalar(2.5);     // [m/s^2] lateral acceleration limit
  Scalar kappa_max = Scalar(0.2);     // [1/m] curvature (steering) limit
};

// The speed limit on a path of curvature `kappa`: the road's limit, and the
// speed at which the lateral acceleration v^2 |kappa| reaches a_lat_max.
inline Scalar curve_speed_limit(const VehicleLimits& lim, Scalar kappa) {
  constexpr Scalar kKappaFloor = Scalar(1e-4);  // [1/m] straighter: only the road's limit
  const Scalar k = std::fabs(kappa);
  if (k <= kKappaFloor) {
    return lim.speed_limit;
  }
  const Scalar v = std::sqrt(lim.a_lat_max / k);
  return v < lim.speed_limit ? v : lim.speed_limit;
}

}  // namespace itp::decision
