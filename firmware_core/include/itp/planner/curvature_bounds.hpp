#pragma once
// The curvature the path QP may use, |l''| + kappa_ref within a bound
// kappa_b(s) per SL sample (paper 1.2, eq. 8): the reference's own curvature
// sampled over the horizon, and three bounds from the lateral-acceleration
// limit a_lat at the speed the ego will have at each s:
//   expected:  min(kappa_max, a_lat / v_guess(s)^2)     at the guessed speed;
//   reach:     min(kappa_max, a_lat / v_min(s)^2)       at the slowest speed braking
//              can reach there (when the expected one cannot be met);
//   evasive:   the same with the evasive lateral acceleration.
// Every bound is at least the reference's |kappa| + 0.002 (the speed stage
// slows the ego for the road's own curves), and at most kappa_max.
#include <array>

#include "itp/decision/curvature_profile.hpp"
#include "itp/decision/motion_limits.hpp"
#include "itp/geometry/reference_line.hpp"

namespace itp::planner {

template <class Cfg>
struct BasicCurvatureBounds {
  using Profile = decision::BasicCurvatureProfile<Cfg>;
  using StSamples = std::array<Scalar, Cfg::kStSamples>;

  Profile reference;  // kappa_ref(s) over the SL horizon
  Profile expected;   // at the expected speed
  Profile reach;      // at the slowest reachable speed
  Profile evasive;    // ... with the evasive lateral acceleration

  // kappa_ref(s) at kCurvatureSamples points over [s0, s0 + length].
  void sample_reference(const geometry::BasicReferenceLine<Cfg>& line, Scalar s0, Scalar length);
  // `expected` from the guessed motion: speed-s `s_guess` and speed `v_guess` per ST sample.
  void update_expected(const StSamples& s_guess, const StSamples& v_guess,
                       const decision::MotionLimits& limits);
  // `reach` (lateral acceleration limits.lat_acc_max) and `evasive`
  // (evasive_lat_acc, never below it) for an ego starting at speed v0.
  void update_reachable(Scalar v0, Scalar evasive_lat_acc, const decision::MotionLimits& limits);
};

}  // namespace itp::planner
