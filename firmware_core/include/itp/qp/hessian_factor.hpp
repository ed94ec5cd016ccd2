#pragma once
// Factorising H at a cold or warm start, and telling a singular (convex) H
// from an indefinite (non-convex) one.
//
// 1. Cholesky of H. Success: H is positive definite, the solver runs as it
//    always did (no proximal term, bit-identical results).
// 2. A pivot failed at row i. With L11 the factor of the leading i x i block and
//    l = L(i, 0..i-1), the direction v = [-L11^-T l; 1; 0...] has
//        v' H v = H(i,i) - |l|^2 = the failed pivot s,
//    so v is a witness: if v'Hv, recomputed from H itself, is clearly negative
//    (below the rounding bound 16 (2Bw+1) eps max|H_ij| |v|^2), H has a negative
//    eigenvalue -> kNotConvex. A pivot that failed only by rounding (v'Hv ~ 0)
//    means H is singular to working precision, i.e. semidefinite.
// 3. Semidefinite: factor H + eps I instead (eps = settings.proximal_weight, or
//    automatic: 1e-6 max H(i,i) in double, 1e-3 in float). The solver then runs
//    proximal-point iterations (proximal.hpp), whose fixed point is the exact
//    optimum of the original QP. If H + eps I fails too, the same witness test
//    at its failing row certifies v'Hv <= -eps|v|^2 < 0 (not convex); a witness
//    that does not certify is numerical trouble.
// Scratch: ws.u holds v, ws.scratch2 holds Hv (both free at a cold start).
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "itp/qp/banded_cholesky.hpp"
#include "itp/qp/problem.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp {

enum class HessianKind : std::uint8_t {
  kPositiveDefinite,  // ws.chol = chol(H)
  kSemidefinite,      // ws.chol = chol(H + eps I), eps in weight_out
  kNegativeCurvature, // a witness v with v'Hv < 0 was found
  kFailed,            // neither factor nor witness: numerical trouble
};

namespace detail {

// Automatic proximal weight relative to the largest diagonal entry of H.
template <typename S>
constexpr S kAutoProximalRelative = std::is_same_v<S, double> ? S(1e-6) : S(1e-3);

// True if the failed pivot at row i has a witness v with v'Hv clearly < 0.
template <class D>
bool has_negative_curvature(const QpProblem<D>& p, QpWorkspace<D>& ws, int i, typename D::Scalar hmax_abs) {
  using S = typename D::Scalar;
  constexpr int kBw = D::kBandwidth;
  S* v = ws.u;
  S* hv = ws.scratch2;
  for (int j = 0; j < p.n; ++j) v[j] = S(0);
  const int j0 = i - kBw > 0 ? i - kBw : 0;
  for (int j = j0; j < i; ++j) v[j] = -ws.chol[i][i - j];
  band::backward_solve(ws.chol, i, v);  // v1 = -L11^-T l (rows 0..i-1 are a valid factor)
  v[i] = S(1);
  band::multiply(p.h_band, p.n, v, hv);
  S curvature = S(0), norm2 = S(0);
  for (int j = 0; j < p.n; ++j) {
    curvature += v[j] * hv[j];
    norm2 += v[j] * v[j];
  }
  const S bound = S(16) * static_cast<S>(2 * kBw + 1) * std::numeric_limits<S>::epsilon() * hmax_abs * norm2;
  return curvature < -bound;  // false for NaN too
}

}  // namespace detail

template <class D>
HessianKind factor_hessian(const QpProblem<D>& p, QpWorkspace<D>& ws, typename D::Scalar requested_weight,
                           typename D::Scalar& weight_out) {
  using S = typename D::Scalar;
  weight_out = S(0);
  const int failed = band::cholesky_failing_row(p.h_band, ws.chol, p.n, S(0));
  if (failed < 0) return HessianKind::kPositiveDefinite;
  S hdiag = S(0), habs = S(0);
  for (int i = 0; i < p.n; ++i) {
    for (int k = 0; k <= D::kBandwidth && k <= i; ++k) {
      const S a = std::abs(p.h_band[i][k]);
      if (a > habs) habs = a;
    }
    if (p.h_band[i][0] > hdiag) hdiag = p.h_band[i][0];
  }
  if (detail::has_negative_curvature(p, ws, failed, habs)) return HessianKind::kNegativeCurvature;
  const S eps = requested_weight > S(0) ? requested_weight
                                        : detail::kAutoProximalRelative<S> * (hdiag > S(0) ? hdiag : S(1));
  const int failed_shifted = band::cholesky_failing_row(p.h_band, ws.chol, p.n, eps);
  if (failed_shifted < 0) {
    weight_out = eps;
    return HessianKind::kSemidefinite;
  }
  // chol now holds the factor of H + eps I up to the failing row; the witness
  // built from it satisfies v'(H + eps I)v ~ s <= 0, i.e. v'Hv <= -eps |v|^2.
  return detail::has_negative_curvature(p, ws, failed_shifted, habs) ? HessianKind::kNegativeCurvature
                                                                     : HessianKind::kFailed;
}

}  // namespace itp::qp
