#include "itp/speed/keep_ahead.hpp"

#include <cmath>
#include <limits>

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"

namespace itp::speed {
namespace {

template <class Cfg>
constexpr Scalar kDt = Cfg::kSpeedHorizon / static_cast<Scalar>(Cfg::kSpeedSamples);  // [s]
constexpr Scalar kRampTime = Scalar(0.5);  // [s] one speed-QP block

// The ego holding its speed up to sample m, then braking (latest_braking in
// keep_ahead.hpp), stepped sample by sample: no arrays (the ST graph's build
// is on the firmware's deepest stack path, and RAM is budgeted).
template <class Cfg>
class Motion {
 public:
  Motion(const BasicStParams<Cfg>& p, int m, Scalar decel)
      : m_(m), decel_(decel), a_start_(min_of(p.a0, p.limits.a_max)), v_(max_of(p.v0, Scalar(0))), a_(a_start_) {}

  Scalar s() const { return s_; }
  Scalar v() const { return v_; }

  // From sample k to k + 1.
  void step(int k) {
    Scalar a_next = 0;
    if (k < m_) {
      const Scalar t = kDt<Cfg> * static_cast<Scalar>(k + 1);
      a_next = t < kRampTime ? a_start_ * (Scalar(1) - t / kRampTime) : Scalar(0);
    } else {
      if (k == m_) {
        rate_ = max_of(a_ - decel_, Scalar(0)) / kRampTime;  // [m/s^3] to decel within one block
      }
      a_next = max_of(decel_, a_ - rate_ * kDt<Cfg>);
    }
    // Stopping within the step counts as the whole step at the mean of v and
    // 0: more than the true distance (upper bounds stay kept).
    const Scalar v_next = max_of(v_ + Scalar(0.5) * (a_ + a_next) * kDt<Cfg>, Scalar(0));
    s_ += Scalar(0.5) * (v_ + v_next) * kDt<Cfg>;
    v_ = v_next;
    a_ = v_ > 0 ? a_next : Scalar(0);
  }

  // An upper bound of the distance still to go to a stop once braking (after
  // the horizon): the rest of the ramp at the highest speed it reaches, then
  // braking at decel from the speed at the ramp's end.
  Scalar stopping_distance() const {
    if (!(v_ > 0)) {
      return 0;
    }
    const Scalar rate = rate_ > 0 ? rate_ : max_of(a_ - decel_, Scalar(0)) / kRampTime;
    const Scalar tau = rate > 0 ? max_of(a_ - decel_, Scalar(0)) / rate : Scalar(0);  // [s] ramp left
    const Scalar v_top = v_ + (a_ > 0 ? a_ * a_ / (Scalar(2) * rate) : Scalar(0));
    const Scalar v_end = max_of(v_ + Scalar(0.5) * (a_ + decel_) * tau, Scalar(0));
    return v_top * tau + v_end * v_end / (Scalar(-2) * decel_);
  }

 private:
  int m_;
  Scalar decel_;
  Scalar a_start_;
  Scalar s_ = 0;
  Scalar v_;
  Scalar a_;
  Scalar rate_ = 0;
};

// Whether the motion with switch m keeps s_hi (below s_limit) and v_hi at
// every sample, and stops before a stop at the horizon's end.
template <class Cfg>
bool keeps_bounds(const BasicStParams<Cfg>& p, const BasicSpeedBounds<Cfg>& b, int m, Scalar decel, Scalar s_limit,
                  Scalar tolerance) {
  constexpr Scalar kSpeedTolerance = Scalar(0.01);  // [m/s]
  Motion<Cfg> w(p, m, decel);
  for (int k = 0; k + 1 < Cfg::kStSamples; ++k) {  // Cfg::kStSamples - 1 steps
    w.step(k);
    const auto u = static_cast<std::size_t>(k + 1);
    if ((b.s_hi[u] < s_limit && w.s() > b.s_hi[u] + tolerance) || w.v() > b.v_hi[u] + kSpeedTolerance) {
      return false;
    }
  }
  const auto last = static_cast<std::size_t>(Cfg::kStSamples - 1);
  // A stop at the horizon's end stays: the motion must stop before it after
  // the horizon too (braking after the horizon when it holds to the end).
  return !(b.s_hi[last] < s_limit) || w.s() + w.stopping_distance() <= b.s_hi[last] + tolerance;
}

}  // namespace

template <class Cfg>
int latest_braking(const BasicStParams<Cfg>& p, const BasicSpeedBounds<Cfg>& b, Scalar decel, Scalar s_limit,
                   Scalar tolerance) {
  // The latest switch first (the common case: no stop within reach), then a
  // bisection for the latest that keeps the bounds (a later switch is a
  // motion further along; every result is checked, so a bound that breaks
  // the order costs keep-ahead room, never feasibility).
  // WCET: <= 2 + log2(Cfg::kStSamples) motions of Cfg::kStSamples steps.
  int hi = Cfg::kStSamples - 1;
  if (keeps_bounds(p, b, hi, decel, s_limit, tolerance)) {
    return hi;
  }
  if (!keeps_bounds(p, b, 0, decel, s_limit, tolerance)) {
    return -1;
  }
  int lo = 0;  // keeps the bounds; hi does not
  while (hi - lo > 1) {  // <= log2(Cfg::kStSamples) bisections
    const int mid = (lo + hi) / 2;
    if (keeps_bounds(p, b, mid, decel, s_limit, tolerance)) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

template <class Cfg>
void braking_motion(const BasicStParams<Cfg>& p, int m, Scalar decel, std::array<Scalar, Cfg::kStSamples>& s) {
  Motion<Cfg> w(p, m, decel);
  s[0] = 0;
  for (int k = 0; k + 1 < Cfg::kStSamples; ++k) {  // Cfg::kStSamples - 1 steps
    w.step(k);
    s[static_cast<std::size_t>(k + 1)] = w.s();
  }
}

template <class Cfg>
bool keep_ahead(const BasicStDecision<Cfg>& d, const BasicDynamicTrack<Cfg>& tr,
                const path::BasicPathResult<Cfg>& path, const BasicStParams<Cfg>& p, int m, Scalar decel,
                BasicSpeedBounds<Cfg>& b) {
  constexpr Scalar kInLine = Scalar(0.5);  // [m] beyond the ego's half width: beside it, not behind
  // Kept from the motion: the speed QP's C2 spline follows its acceleration
  // ramps only approximately.
  constexpr Scalar kSlack = Scalar(0.2);       // [m]
  constexpr Scalar kSlackRate = Scalar(0.05);  // [m/s] more per second on
  bool raised = false;
  Motion<Cfg> w(p, m, decel);
  for (int k = 0; k <= d.k2 && k < Cfg::kStSamples; ++k) {  // <= Cfg::kStSamples
    if (k > 0) {
      w.step(k - 1);
    }
    const auto u = static_cast<std::size_t>(k);
    // At the speed spline's knots only: between them the spline follows the
    // knots closely, and a bound at every sample made the speed QP activate
    // one row after the other (tens of active-set iterations per solve).
    if (k < d.k1 || !d.conflict[u] || k % Cfg::kSpeedSamplesPerBlock != 0) {
      continue;
    }
    const geometry::SlBox& box = tr.box[u];
    const Scalar s_mid = Scalar(0.5) * (box.s_min + box.s_max);
    if (std::fabs(Scalar(0.5) * (box.l_min + box.l_max) - path.eval(s_mid, 0)) > p.half_width + kInLine) {
      continue;
    }
    const Scalar lo = min_of(d.s_hi[u], w.s() - kSlack - kSlackRate * kDt<Cfg> * static_cast<Scalar>(k));
    if (lo > b.s_lo[u]) {
      b.s_lo[u] = lo;
      raised = true;
    }
  }
  return raised;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                                   \
  template int latest_braking<C>(const BasicStParams<C>&, const BasicSpeedBounds<C>&, Scalar, Scalar, Scalar); \
  template void braking_motion<C>(const BasicStParams<C>&, int, Scalar, std::array<Scalar, C::kStSamples>&);  \
  template bool keep_ahead<C>(const BasicStDecision<C>&, const BasicDynamicTrack<C>&,                        \
                              const path::BasicPathResult<C>&, const BasicStParams<C>&, int, Scalar,         \
                              BasicSpeedBounds<C>&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::speed
