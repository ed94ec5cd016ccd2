#pragma once
// Angle helpers. Angles are [rad], counter-clockwise from +x.
#include <cmath>

#include "itp/config.hpp"

namespace itp::geometry {

inline constexpr Scalar kPi = Scalar(3.14159265358979323846);

// Wraps an angle into (-pi, pi]. No loop: one remainder, so any finite input
// takes the same time.
inline Scalar wrap_angle(Scalar angle) {
  const Scalar two_pi = Scalar(2) * kPi;
  Scalar a = std::fmod(angle + kPi, two_pi);  // (-2pi, 2pi)
  if (a <= Scalar(0)) {
    a += two_pi;
  }
  return a - kPi;
}

}  // namespace itp::geometry
