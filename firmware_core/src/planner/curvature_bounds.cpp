#include "itp/planner/curvature_bounds.hpp"

#include <cmath>

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"

namespace itp::planner {
namespace {

constexpr Scalar kReferenceSlack = Scalar(0.002);  // [1/m] above the reference's own |kappa|
constexpr Scalar kBrakeOnset = Scalar(0.3);        // [s] as the ST graph's braking model

// The bound never falls below the reference's own curvature (plus slack).
Scalar at_least_reference(Scalar bound, Scalar kappa_ref, Scalar kappa_max) {
  return max_of(bound, min_of(std::fabs(kappa_ref) + kReferenceSlack, kappa_max));
}

// min(kappa_max, a_lat / v_min(s)^2) with v_min(s) the slowest speed at path
// distance s braking at the limit after the onset, for each sample of `out`.
template <class Cfg>
void reachable_bound(const decision::BasicCurvatureProfile<Cfg>& ref, Scalar v0, Scalar a_lat,
                     const decision::MotionLimits& limits, decision::BasicCurvatureProfile<Cfg>& out) {
  out.s0 = ref.s0;
  out.ds = ref.ds;
  const Scalar v = max_of(v0, Scalar(0));
  const Scalar brake = -limits.a_min;  // > 0
  for (std::size_t i = 0; i < static_cast<std::size_t>(Cfg::kCurvatureSamples); ++i) {  // Cfg::kCurvatureSamples
    const Scalar s = ref.ds * static_cast<Scalar>(i);
    const Scalar braked = max_of(s - v * kBrakeOnset, Scalar(0));
    const Scalar v_min = std::sqrt(max_of(v * v - Scalar(2) * brake * braked, Scalar(0)));
    const Scalar kb = v_min > Scalar(1) ? min_of(limits.kappa_max, a_lat / (v_min * v_min)) : limits.kappa_max;
    out.kappa[i] = at_least_reference(kb, ref.kappa[i], limits.kappa_max);
  }
}

}  // namespace

template <class Cfg>
void BasicCurvatureBounds<Cfg>::sample_reference(const geometry::BasicReferenceLine<Cfg>& line,
                                                 Scalar s0, Scalar length) {
  reference.s0 = s0;
  reference.ds = length / static_cast<Scalar>(Cfg::kCurvatureSamples - 1);
  for (int i = 0; i < Cfg::kCurvatureSamples; ++i) {  // Cfg::kCurvatureSamples
    reference.kappa[static_cast<std::size_t>(i)] =
        line.evaluate(reference.s0 + reference.ds * static_cast<Scalar>(i)).kappa;
  }
}

template <class Cfg>
void BasicCurvatureBounds<Cfg>::update_expected(const StSamples& s_guess, const StSamples& v_guess,
                                                const decision::MotionLimits& limits) {
  expected.s0 = reference.s0;
  expected.ds = reference.ds;
  std::size_t k = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(Cfg::kCurvatureSamples); ++i) {  // Cfg::kCurvatureSamples
    const Scalar s_rel = reference.ds * static_cast<Scalar>(i);
    while (k + 1 < static_cast<std::size_t>(Cfg::kStSamples) &&
           s_guess[k + 1] < s_rel) {  // monotone, < Cfg::kStSamples in all
      ++k;
    }
    const Scalar v = max_of(v_guess[k], Scalar(1));
    const Scalar kb = min_of(limits.kappa_max, limits.lat_acc_max / (v * v));
    expected.kappa[i] = at_least_reference(kb, reference.kappa[i], limits.kappa_max);
  }
}

template <class Cfg>
void BasicCurvatureBounds<Cfg>::update_reachable(Scalar v0, Scalar evasive_lat_acc,
                                                 const decision::MotionLimits& limits) {
  reachable_bound(reference, v0, limits.lat_acc_max, limits, reach);
  reachable_bound(reference, v0, max_of(limits.lat_acc_max, evasive_lat_acc), limits, evasive);
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C) template struct BasicCurvatureBounds<C>;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::planner
