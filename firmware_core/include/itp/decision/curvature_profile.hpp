#pragma once
// κ_ref(s) of the reference line, sampled uniformly over the horizon so that
// the decision and speed stages need not query the reference line per sample.
#include <array>

#include "itp/config.hpp"

namespace itp::decision {

inline constexpr int kCurvatureSamples = 101;  // 1 m spacing over the 100 m horizon

struct CurvatureProfile {
  Scalar s0 = 0;                   // [m] first sample
  Scalar ds = Scalar(1);           // [m] spacing
  std::array<Scalar, kCurvatureSamples> kappa{};  // [1/m]

  // Linear interpolation, clamped at the ends.
  Scalar at(Scalar s) const {
    const Scalar u = (s - s0) / ds;
    if (!(u > 0)) {
      return kappa[0];
    }
    const int i = static_cast<int>(u);
    if (i >= kCurvatureSamples - 1) {
      return kappa[kCurvatureSamples - 1];
    }
    const Scalar f = u - static_cast<Scalar>(i);
    return kappa[static_cast<std::size_t>(i)] * (Scalar(1) - f) +
           kappa[static_cast<std::size_t>(i + 1)] * f;
  }
};

}  // namespace itp::decision
