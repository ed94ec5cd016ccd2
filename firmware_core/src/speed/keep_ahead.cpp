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
// Steps of braking simulated beyond the horizon: from 60 m/s at 3 m/s^2
// after the ramp, at the default 0.1 s.
constexpr int kStopSteps = 210;

}  // namespace

template <class Cfg>
void holding(const BasicStParams<Cfg>& p, const BasicSpeedBounds<Cfg>& b, Scalar decel, BasicEgoProfile<Cfg>& r) {
  constexpr int kN = Cfg::kStSamples;
  // The speed bound as a motion can meet it: where it drops faster than
  // braking at `decel` takes the speed down, the bound before it is lowered
  // (backwards).
  r.v_cap[static_cast<std::size_t>(kN - 1)] = max_of(b.v_hi[static_cast<std::size_t>(kN - 1)], Scalar(0));
  for (int k = kN - 2; k >= 0; --k) {  // Cfg::kStSamples - 1
    const auto u = static_cast<std::size_t>(k);
    r.v_cap[u] = max_of(min_of(b.v_hi[u], r.v_cap[u + 1] - decel * kDt<Cfg>), Scalar(0));
  }
  Scalar s = 0;
  Scalar v = max_of(p.v0, Scalar(0));
  const Scalar a_start = min_of(p.a0, p.limits.a_max);
  for (int k = 0; k < kN; ++k) {  // Cfg::kStSamples
    const auto u = static_cast<std::size_t>(k);
    const Scalar t = kDt<Cfg> * static_cast<Scalar>(k);
    const Scalar ramp = t < kRampTime ? t / kRampTime : Scalar(1);
    const Scalar a = a_start * (Scalar(1) - ramp);
    r.s[u] = s;
    r.v[u] = v;
    r.a[u] = a;
    if (k + 1 == kN) {
      break;
    }
    // Below the next sample's cap, as far as braking at decel gets there.
    const Scalar cap = max_of(r.v_cap[u + 1], v + decel * kDt<Cfg>);
    const Scalar v_next = max_of(min_of(v + a * kDt<Cfg>, cap), Scalar(0));
    s += Scalar(0.5) * (v + v_next) * kDt<Cfg>;
    v = v_next;
  }
}

template <class Cfg>
bool latest_braking(const BasicSpeedBounds<Cfg>& b, const BasicEgoProfile<Cfg>& r, Scalar decel, Scalar s_limit,
                    Scalar tolerance, std::array<Scalar, Cfg::kStSamples>& late) {
  constexpr int kN = Cfg::kStSamples;
  const auto keeps = [&](int k, Scalar s) {
    const Scalar hi = b.s_hi[static_cast<std::size_t>(k)];
    return hi >= s_limit || s <= hi + tolerance;
  };
  const bool stop_at_end = b.s_hi[static_cast<std::size_t>(kN - 1)] < s_limit;
  // The held motion itself keeps the bounds up to sample `prefix` - 1.
  int prefix = 0;
  while (prefix < kN && keeps(prefix, r.s[static_cast<std::size_t>(prefix)])) {  // <= Cfg::kStSamples
    ++prefix;
  }
  for (int m = prefix - 1; m >= 0; --m) {  // <= Cfg::kStSamples switches, the latest first
    const auto um = static_cast<std::size_t>(m);
    Scalar s = r.s[um];
    Scalar v = r.v[um];
    Scalar a = r.a[um];
    const Scalar rate = max_of(a - decel, Scalar(0)) / kRampTime;  // [m/s^3]
    bool ok = true;
    for (int j = m + 1; j < kN && ok; ++j) {  // Cfg::kStSamples
      const Scalar a_next = max_of(decel, a - rate * kDt<Cfg>);
      Scalar v_next = v + Scalar(0.5) * (a + a_next) * kDt<Cfg>;
      // Stopping within the step: counted as the whole step at the mean of v
      // and 0, more than the true distance (upper bounds stay kept). Below
      // the speed cap (it drops no faster than braking at decel).
      v_next = max_of(min_of(v_next, r.v_cap[static_cast<std::size_t>(j)]), Scalar(0));
      s += Scalar(0.5) * (v + v_next) * kDt<Cfg>;
      v = v_next;
      a = v > 0 ? a_next : Scalar(0);
      ok = keeps(j, s);
    }
    // A stop at the horizon's end stays: the motion must stop before it
    // beyond the horizon too (at most kStopSteps more steps; the speed cap
    // no longer applies).
    for (int j = 0; j < kStopSteps && ok && v > 0 && stop_at_end; ++j) {  // kStopSteps
      const Scalar a_next = max_of(decel, a - rate * kDt<Cfg>);
      const Scalar v_next = max_of(v + Scalar(0.5) * (a + a_next) * kDt<Cfg>, Scalar(0));
      s += Scalar(0.5) * (v + v_next) * kDt<Cfg>;
      v = v_next;
      a = a_next;
      ok = keeps(kN - 1, s);
    }
    if (!ok || (stop_at_end && v > 0)) {
      continue;
    }
    // Fill the motion: held up to m, braking after it (as simulated).
    s = r.s[um];
    v = r.v[um];
    a = r.a[um];
    for (int j = 0; j < kN; ++j) {  // Cfg::kStSamples
      const auto u = static_cast<std::size_t>(j);
      if (j <= m) {
        late[u] = r.s[u];
        continue;
      }
      const Scalar a_next = max_of(decel, a - rate * kDt<Cfg>);
      const Scalar v_next = max_of(min_of(v + Scalar(0.5) * (a + a_next) * kDt<Cfg>, r.v_cap[u]), Scalar(0));
      s += Scalar(0.5) * (v + v_next) * kDt<Cfg>;
      v = v_next;
      a = v > 0 ? a_next : Scalar(0);
      late[u] = s;
    }
    return true;
  }
  return false;
}

template <class Cfg>
bool keep_ahead(const BasicStDecision<Cfg>& d, const BasicDynamicTrack<Cfg>& tr,
                const path::BasicPathResult<Cfg>& path, const BasicStParams<Cfg>& p,
                const std::array<Scalar, Cfg::kStSamples>& late, BasicSpeedBounds<Cfg>& b) {
  constexpr Scalar kInLine = Scalar(0.5);      // [m] beyond the ego's half width: beside it, not behind
  // Kept from the latest braking: the speed QP's C2 spline follows the
  // profile's acceleration ramps only approximately.
  constexpr Scalar kSlack = Scalar(0.2);      // [m]
  constexpr Scalar kSlackRate = Scalar(0.05);  // [m/s] more per second on
  bool raised = false;
  for (int k = d.k1; k >= 0 && k <= d.k2; ++k) {  // <= Cfg::kStSamples
    const auto u = static_cast<std::size_t>(k);
    // At the speed spline's knots only: between them the spline follows the
    // knots closely, and a bound at every sample made the speed QP activate
    // one row after the other (tens of active-set iterations per solve).
    if (!d.conflict[u] || k % Cfg::kSpeedSamplesPerBlock != 0) {
      continue;
    }
    const geometry::SlBox& box = tr.box[u];
    const Scalar s_mid = Scalar(0.5) * (box.s_min + box.s_max);
    if (std::fabs(Scalar(0.5) * (box.l_min + box.l_max) - path.eval(s_mid, 0)) > p.half_width + kInLine) {
      continue;
    }
    const Scalar lo = min_of(d.s_hi[u], late[u] - kSlack - kSlackRate * kDt<Cfg> * static_cast<Scalar>(k));
    if (lo > b.s_lo[u]) {
      b.s_lo[u] = lo;
      raised = true;
    }
  }
  return raised;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                                   \
  template void holding<C>(const BasicStParams<C>&, const BasicSpeedBounds<C>&, Scalar, BasicEgoProfile<C>&);   \
  template bool latest_braking<C>(const BasicSpeedBounds<C>&, const BasicEgoProfile<C>&, Scalar, Scalar,     \
                                  Scalar, std::array<Scalar, C::kStSamples>&);                               \
  template bool keep_ahead<C>(const BasicStDecision<C>&, const BasicDynamicTrack<C>&,                        \
                              const path::BasicPathResult<C>&, const BasicStParams<C>&,                      \
                              const std::array<Scalar, C::kStSamples>&, BasicSpeedBounds<C>&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::speed
