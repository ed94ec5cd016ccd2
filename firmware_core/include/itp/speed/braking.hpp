#pragma once
// The least distance any speed plan covers: braking after the onset the C2
// speed spline needs to build up its deceleration.
#include "itp/config.hpp"

namespace itp::speed {

// The speed spline is C2 and starts at the current acceleration, so full
// braking cannot begin at once: allow this long to build it up.
inline constexpr Scalar kBrakeOnset = Scalar(0.3);  // [s]

// Distance the ego covers by time t braking at a_min (< 0) after kBrakeOnset
// at v0 (then standing). [m]
inline Scalar braking_distance(Scalar v0, Scalar a_min, Scalar t) {
  if (t <= kBrakeOnset) {
    return v0 * t;
  }
  const Scalar t_stop = v0 / -a_min;
  const Scalar tb = t - kBrakeOnset;
  const Scalar tt = tb < t_stop ? tb : t_stop;
  return v0 * kBrakeOnset + v0 * tt + Scalar(0.5) * a_min * tt * tt;
}

}  // namespace itp::speed
