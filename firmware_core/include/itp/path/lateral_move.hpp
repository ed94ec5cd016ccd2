#pragma once
// How long a lateral move takes along the road: the shortest s-distance over
// which l(s) moves by e, from and back to l' = 0, with |l''| <= kappa (the
// curvature bound, small-angle) and |l'| <= slope. Bang-bang in l'': two arcs,
// e = kappa L^2 / 4, while their steepest slope kappa L / 2 stays within
// `slope`; else a ramp of slope / kappa at each end (each moving l by
// slope^2 / (2 kappa)) and a straight run at `slope` between.
#include <cmath>
#include <limits>

#include "itp/config.hpp"

namespace itp::path {

inline Scalar lateral_move_length(Scalar e, Scalar kappa, Scalar slope) {
  if (!(e > Scalar(0))) return Scalar(0);
  if (!(kappa > Scalar(0))) return std::numeric_limits<Scalar>::infinity();
  const Scalar arcs = Scalar(2) * std::sqrt(e / kappa);
  if (!(slope > Scalar(0)) || kappa * arcs <= Scalar(2) * slope) return arcs;
  return Scalar(2) * slope / kappa + (e - slope * slope / kappa) / slope;
}

}  // namespace itp::path
