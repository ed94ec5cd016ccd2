#pragma once
// Proximal-point iterations for a singular (positive semidefinite) H.
//
// With eps > 0 and a centre x_k, the regularised QP
//     x_k+1 = argmin 1/2 x'Hx + g'x + eps/2 |x - x_k|^2   s.t. the same constraints
//           = argmin 1/2 x'(H + eps I)x + (g - eps x_k)'x
// has a positive definite Hessian, so the dual active-set loop solves it with
// the factor of H + eps I (hessian_factor.hpp); between outer iterations only
// the linear term changes, so each one is a hotstart (same factor of H + eps I,
// same rows of M, the previous working set). Its KKT conditions read
//     H x_k+1 + g + A'y + eps (x_k+1 - x_k) = 0,
// so (x_k+1, y) satisfies the KKT conditions of the ORIGINAL QP up to the
// stationarity residual eps |x_k+1 - x_k|. For a convex QP the iterates
// converge to an optimum of the original problem (Rockafellar 1976; finitely
// for the polyhedral part), and the loop stops at a fixed point, when that
// residual is below stationarity_tolerance (1 + |g|_inf + |Hx|_inf). The
// reported x, y and objective are those of the original problem: exact, not
// perturbed by eps.
//
// Checks along the way, each with its own status:
// - the step d = x_k+1 - x_k is a witness of convexity: d'Hd < 0 beyond
//   rounding proves a negative eigenvalue that H + eps I hid -> kNotConvex;
// - a step with Hd = 0 (to rounding), g'd < 0 and every constraint allowing
//   the whole ray x + t d, t >= 0 (a_c'd <= 0 where ub_c is finite, >= 0 where
//   lb_c is finite) proves that the objective is unbounded below -> kUnbounded.
#include <cmath>
#include <cstdint>
#include <limits>

#include "itp/qp/banded_cholesky.hpp"
#include "itp/qp/problem.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp::prox {

// x_unc = -(H + eps I)^-1 (g - eps centre): the regularised unconstrained optimum.
template <class D>
void unconstrained_optimum(const QpProblem<D>& p, QpWorkspace<D>& ws, const typename D::Scalar* centre) {
  const typename D::Scalar eps = ws.proximal_weight;
  for (int j = 0; j < p.n; ++j) ws.x_unc[j] = -(p.g[j] - eps * centre[j]);
  band::forward_solve(ws.chol, p.n, ws.x_unc, 0);
  band::backward_solve(ws.chol, p.n, ws.x_unc);
}

enum class StepVerdict : std::uint8_t { kContinue, kConverged, kNotConvex, kUnbounded };

// Judges the step from `centre` to ws.x. `steady`: the inner solve changed no
// working-set entry (the only case in which an unbounded ray is looked for).
// Scratch: ws.u holds d, ws.scratch2 holds Hd (both recomputed by the next solve).
template <class D>
StepVerdict judge_step(const QpProblem<D>& p, QpWorkspace<D>& ws, const QpSettings<typename D::Scalar>& s,
                       const typename D::Scalar* centre, bool steady) {
  using S = typename D::Scalar;
  constexpr int kN = D::kMaxVariables;
  const S eps_mach = std::numeric_limits<S>::epsilon();
  S* d = ws.u;
  S* hd = ws.scratch2;
  S dmax = S(0), gmax = S(0), hmax = S(0);
  for (int j = 0; j < p.n; ++j) {
    d[j] = ws.x[j] - centre[j];
    if (!(std::abs(d[j]) <= dmax)) dmax = std::abs(d[j]);
    if (std::abs(p.g[j]) > gmax) gmax = std::abs(p.g[j]);
    for (int k = 0; k <= D::kBandwidth && k <= j; ++k) {
      if (std::abs(p.h_band[j][k]) > hmax) hmax = std::abs(p.h_band[j][k]);
    }
  }
  // Stationarity of the original QP: |H x + g + A'y| = eps |d|.
  band::multiply(p.h_band, p.n, ws.x, hd);
  S hxmax = S(0);
  for (int j = 0; j < p.n; ++j) {
    if (std::abs(hd[j]) > hxmax) hxmax = std::abs(hd[j]);
  }
  if (ws.proximal_weight * dmax <= s.stationarity_tolerance * (S(1) + gmax + hxmax)) {
    return StepVerdict::kConverged;
  }
  if (!(dmax < std::numeric_limits<S>::infinity())) return StepVerdict::kContinue;  // caught by the caller
  band::multiply(p.h_band, p.n, d, hd);
  S dhd = S(0), dd = S(0), gd = S(0), hdmax = S(0);
  for (int j = 0; j < p.n; ++j) {
    dhd += d[j] * hd[j];
    dd += d[j] * d[j];
    gd += p.g[j] * d[j];
    if (std::abs(hd[j]) > hdmax) hdmax = std::abs(hd[j]);
  }
  const S rounding = S(16) * static_cast<S>(2 * D::kBandwidth + 1) * eps_mach * hmax * dd;
  if (dhd < -rounding) return StepVerdict::kNotConvex;
  if (!steady || !(gd < -S(1e3) * eps_mach * gmax * dmax * static_cast<S>(p.n))) return StepVerdict::kContinue;
  // A ray of descent without curvature: every constraint must allow it. An
  // active one (moved along) may show a rounding residue up to `zero`; an
  // inactive one must have the exact sign (a false "unbounded" is worse than
  // running on to the iteration limit).
  const S zero = S(1e3) * eps_mach * static_cast<S>(p.n);
  if (hdmax > zero * hmax * dmax) return StepVerdict::kContinue;
  const S inf = std::numeric_limits<S>::infinity();
  for (int j = 0; j < p.n; ++j) {
    const S slack = ws.active_side[j] != 0 ? zero * dmax : S(0);
    if ((d[j] > slack && p.ub[j] < inf) || (d[j] < -slack && p.lb[j] > -inf)) return StepVerdict::kContinue;
  }
  for (int r = 0; r < p.m; ++r) {
    S ad = S(0), anorm = S(0);
    for (int k = 0; k < p.a_nnz[r]; ++k) {
      ad += p.a_val[r][k] * d[p.a_col[r][k]];
      anorm += std::abs(p.a_val[r][k]);
    }
    const S slack = ws.active_side[kN + r] != 0 ? zero * anorm * dmax : S(0);
    if ((ad > slack && p.uba[r] < inf) || (ad < -slack && p.lba[r] > -inf)) return StepVerdict::kContinue;
  }
  return StepVerdict::kUnbounded;
}

}  // namespace itp::qp::prox
