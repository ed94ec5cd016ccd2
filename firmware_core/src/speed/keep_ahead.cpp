#include "itp/speed/keep_ahead.hpp"

#include <cmath>
#include <limits>

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"
#include "itp/speed/braking.hpp"

namespace itp::speed {
namespace {

template <class Cfg>
constexpr Scalar kDt = Cfg::kSpeedHorizon / static_cast<Scalar>(Cfg::kSpeedSamples);  // [s]

}  // namespace

template <class Cfg>
void reachable(const BasicStParams<Cfg>& p, const BasicSpeedBounds<Cfg>& b,
               std::array<Scalar, Cfg::kStSamples>& s_max) {
  constexpr Scalar kRampTime = Scalar(0.5);  // [s] one speed-QP block
  Scalar s = 0;
  Scalar v = max_of(p.v0, Scalar(0));
  for (int k = 0; k < Cfg::kStSamples; ++k) {  // Cfg::kStSamples
    const auto u = static_cast<std::size_t>(k);
    s_max[u] = s;
    const Scalar t = kDt<Cfg> * static_cast<Scalar>(k);
    const Scalar ramp = t < kRampTime ? t / kRampTime : Scalar(1);
    const Scalar a = min_of(p.a0, p.limits.a_max) + (p.limits.a_max - min_of(p.a0, p.limits.a_max)) * ramp;
    const Scalar v_next = max_of(min_of(v + a * kDt<Cfg>, b.v_hi[u]), Scalar(0));
    s += Scalar(0.5) * (v + v_next) * kDt<Cfg>;
    v = v_next;
  }
}

template <class Cfg>
bool keep_ahead(const BasicStDecision<Cfg>& d, const BasicDynamicTrack<Cfg>& tr,
                const path::BasicPathResult<Cfg>& path, const BasicStParams<Cfg>& p,
                const std::array<Scalar, Cfg::kStSamples>& s_max, BasicSpeedBounds<Cfg>& b) {
  constexpr Scalar kInLine = Scalar(0.5);   // [m] beyond the ego's half width: beside it, not behind
  constexpr Scalar kReachSlack = Scalar(0.2);  // [m] kept from the furthest reachable position
  const Scalar path_limit = p.path_end >= 0 ? p.path_end - p.s0 - p.front : std::numeric_limits<Scalar>::infinity();
  bool raised = false;
  for (int k = d.k1; k >= 0 && k <= d.k2; ++k) {  // <= Cfg::kStSamples
    const auto u = static_cast<std::size_t>(k);
    if (!d.conflict[u]) {
      continue;
    }
    const geometry::SlBox& box = tr.box[u];
    const Scalar s_mid = Scalar(0.5) * (box.s_min + box.s_max);
    if (std::fabs(Scalar(0.5) * (box.l_min + box.l_max) - path.eval(s_mid, 0)) > p.half_width + kInLine) {
      continue;
    }
    const Scalar v = min_of(max_of(d.speed[u], Scalar(0)), b.v_hi[u]);
    Scalar lo = min_of(d.s_hi[u], s_max[u] - kReachSlack);
    for (int j = k; j < Cfg::kStSamples; ++j) {  // Cfg::kStSamples
      const auto w = static_cast<std::size_t>(j);
      if (b.s_hi[w] < path_limit) {
        lo = min_of(lo, b.s_hi[w] - braking_distance(v, p.comfort_decel, kDt<Cfg> * static_cast<Scalar>(j - k)));
      }
    }
    if (lo > b.s_lo[u]) {
      b.s_lo[u] = lo;
      raised = true;
    }
  }
  return raised;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                           \
  template void reachable<C>(const BasicStParams<C>&, const BasicSpeedBounds<C>&,                    \
                             std::array<Scalar, C::kStSamples>&);                                    \
  template bool keep_ahead<C>(const BasicStDecision<C>&, const BasicDynamicTrack<C>&,                \
                              const path::BasicPathResult<C>&, const BasicStParams<C>&,              \
                              const std::array<Scalar, C::kStSamples>&, BasicSpeedBounds<C>&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::speed
