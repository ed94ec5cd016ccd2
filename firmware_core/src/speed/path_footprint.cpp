#include "itp/speed/path_footprint.hpp"

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"
#include "itp/geometry/frenet.hpp"

namespace itp::speed {
namespace {

constexpr int kProbes = 12;                     // path probes across an obstacle's s-extent
constexpr Scalar kLateralSlack = Scalar(1e-6);  // [m] far above the rounding of either side

// Block of the path that eval() uses at s (clamped to the horizon).
template <class Cfg>
int block_at(const path::BasicPathResult<Cfg>& path, Scalar s) {
  const Scalar u = (s - path.s0) / path.h;
  return !(u >= 1) ? 0 : (u >= static_cast<Scalar>(Cfg::kPathBlocks) ? Cfg::kPathBlocks - 1 : static_cast<int>(u));
}

}  // namespace

template <class Cfg>
Scalar speed_limit_at(const path::BasicPathResult<Cfg>& path, const BasicStParams<Cfg>& p,
                      Scalar s) {
  geometry::FrenetState f;
  f.l = path.eval(s, 0);
  f.dl = path.eval(s, 1);
  f.ddl = path.eval(s, 2);
  if (p.kappa_ref != nullptr) {
    f.ref_kappa = p.kappa_ref->at(s);
    f.ref_dkappa = p.kappa_ref->slope(s);
  }
  const geometry::CartesianMotion m = geometry::cartesian_motion(f);
  return decision::curve_speed_limit(p.limits, m.kappa) / m.scale;
}

template <class Cfg>
void lateral_range(const path::BasicPathResult<Cfg>& path, LateralRange<Cfg>& r) {
  for (int k = 0; k < Cfg::kPathBlocks; ++k) {  // kPathBlocks
    const Scalar* c = path.coefficients.data() + 6 * k;
    const Scalar h = path.h;
    const Scalar a1 = c[1] * h;
    const Scalar a2 = c[2] * h * h;
    const Scalar a3 = c[3] * h * h * h;
    const Scalar a4 = c[4] * h * h * h * h;
    const Scalar a5 = c[5] * h * h * h * h * h;
    const std::array<Scalar, 6> b{c[0],
                                 c[0] + a1 / 5,
                                 c[0] + Scalar(2) * a1 / 5 + a2 / 10,
                                 c[0] + Scalar(3) * a1 / 5 + Scalar(3) * a2 / 10 + a3 / 10,
                                 c[0] + Scalar(4) * a1 / 5 + Scalar(6) * a2 / 10 + Scalar(4) * a3 / 10 + a4 / 5,
                                 c[0] + a1 + a2 + a3 + a4 + a5};
    Scalar lo = b[0];
    Scalar hi = b[0];
    for (const Scalar v : b) {  // 6 coefficients
      lo = min_of(lo, v);
      hi = max_of(hi, v);
    }
    r.lo[static_cast<std::size_t>(k)] = lo - kLateralSlack;
    r.hi[static_cast<std::size_t>(k)] = hi + kLateralSlack;
  }
}

template <class Cfg>
bool path_conflicts(const path::BasicPathResult<Cfg>& path, const LateralRange<Cfg>& range, const BasicStParams<Cfg>& p,
                    const geometry::SlBox& b, Scalar lateral_margin) {
  const Scalar reach = p.half_width + lateral_margin;
  if (path.h > 0) {
    const int k0 = block_at(path, b.s_min) - 1;  // one block of margin each side (the probes' rounding)
    const int k1 = block_at(path, b.s_max) + 1;
    Scalar lo = range.lo[static_cast<std::size_t>(k0 < 0 ? 0 : k0)];
    Scalar hi = range.hi[static_cast<std::size_t>(k0 < 0 ? 0 : k0)];
    for (int k = k0 < 0 ? 0 : k0; k <= k1 && k < Cfg::kPathBlocks; ++k) {  // <= kPathBlocks
      lo = min_of(lo, range.lo[static_cast<std::size_t>(k)]);
      hi = max_of(hi, range.hi[static_cast<std::size_t>(k)]);
    }
    if (hi + reach <= b.l_min || lo - reach >= b.l_max) {
      return false;  // no probe can overlap: the same answer without the 13 evaluations
    }
  }
  for (int i = 0; i <= kProbes; ++i) {  // kProbes + 1 probes
    const Scalar s = b.s_min + (b.s_max - b.s_min) * static_cast<Scalar>(i) / static_cast<Scalar>(kProbes);
    if (s < p.s0 - p.rear) {
      continue;
    }
    const Scalar l = path.eval(s, 0);
    if (l + reach > b.l_min && l - reach < b.l_max) {
      return true;
    }
  }
  return false;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                          \
  template Scalar speed_limit_at<C>(const path::BasicPathResult<C>&, const BasicStParams<C>&, Scalar); \
  template void lateral_range<C>(const path::BasicPathResult<C>&, LateralRange<C>&);              \
  template bool path_conflicts<C>(const path::BasicPathResult<C>&, const LateralRange<C>&,        \
                                  const BasicStParams<C>&, const geometry::SlBox&, Scalar);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::speed
