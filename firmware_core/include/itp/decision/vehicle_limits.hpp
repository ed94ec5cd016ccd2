#pragma once
// Dynamic limits the decision, path and speed stages respect.
#include "itp/config.hpp"

namespace itp::decision {

struct VehicleLimits {
  Scalar speed_limit = Scalar(16.7);  // [m/s] road speed limit
  Scalar a_max = Scalar(2.0);         // [m/s^2] comfortable acceleration
  Scalar a_min = Scalar(-4.0);        // [m/s^2] braking limit (negative)
  Scalar a_lat_max = Scalar(2.5);     // [m/s^2] lateral acceleration limit
  Scalar kappa_max = Scalar(0.2);     // [1/m] curvature (steering) limit
};

}  // namespace itp::decision
