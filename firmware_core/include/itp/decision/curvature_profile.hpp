#pragma once
// κ_ref(s) of the reference line, sampled uniformly over the horizon so that
// the decision and speed stages need not query the reference line per sample.
#include <array>

#include "itp/config.hpp"

namespace itp::decision {

// Cfg::kCurvatureSamples samples: 1 m spacing over the SL horizon.
template <class Cfg>
struct BasicCurvatureProfile {
  static constexpr int kSamples = Cfg::kCurvatureSamples;

  Scalar s0 = 0;                   // [m] first sample
  Scalar ds = Scalar(1);           // [m] spacing
  std::array<Scalar, Cfg::kCurvatureSamples> kappa{};  // [1/m]

  // Linear interpolation, clamped at the ends.
  Scalar at(Scalar s) const {
    const Scalar u = (s - s0) / ds;
    if (!(u > 0)) {
      return kappa[0];
    }
    const int i = static_cast<int>(u);
    if (i >= kSamples - 1) {
      return kappa[kSamples - 1];
    }
    const Scalar f = u - static_cast<Scalar>(i);
    return kappa[static_cast<std::size_t>(i)] * (Scalar(1) - f) +
           kappa[static_cast<std::size_t>(i + 1)] * f;
  }
  // d kappa / ds [1/m^2]: central difference over one spacing.
  Scalar slope(Scalar s) const { return (at(s + ds) - at(s - ds)) / (Scalar(2) * ds); }
};

using CurvatureProfile = BasicCurvatureProfile<DefaultConfig>;

}  // namespace itp::decision
