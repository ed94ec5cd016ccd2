#pragma once
// The check of an infeasibility certificate, from the problem data alone
// (never from solver state), so that `kInfeasible` means infeasible.
//
// Farkas: the constraints  lb_c <= a_c'x <= ub_c  (rows of A and the bounds,
// a_j = e_j) have no solution if some y (y_c > 0: upper side, y_c < 0: lower
// side, the side's bound finite) has
//     r = sum_c y_c a_c = 0   and   support(y) = sum_{y_c>0} y_c ub_c + sum_{y_c<0} y_c lb_c < 0,
// because every feasible x gives  y_c a_c'x <= (y_c's side bound) y_c  term by
// term, so r'x <= support(y) < 0, impossible for r = 0. The dual active-set
// loop finds such a y as a dual ray (active_set.hpp). In floating point r is
// small, not zero; every feasible x must still satisfy
//     -gap = support(y) >= r'x >= -sum_j |r_j| |x_j|.
// So the ray proves infeasibility wherever sum_j |r_j| X_j < gap, X_j a bound
// of |x_j| on the feasible set: max(|lb_j|, |ub_j|) for a boxed variable (a
// rigorous proof), and for a variable without both bounds `radius` times the
// data's scale 1 + max(|b_c|/|a_c| over the bounds the ray uses, the finite
// bounds of x): the ray then proves that no feasible point lies within that
// radius (1e5 times the scale by default), far beyond any point the solver
// could have returned. A ray computed from a wrong working set has a residual
// of the order of its gap and fails. r and support(y) are computed in working
// precision, so each side carries a bound of its own rounding error,
// (k + 2) eps times the sum of the absolute terms, k the number of terms. y is first
// normalised to max_c |y_c| |a_c| = 1, so scaling a row does not change the
// verdict. A ray that fails the test is numerical trouble, never kInfeasible.
#include <cmath>
#include <limits>

#include "itp/qp/problem.hpp"
#include "itp/qp/row_scaling.hpp"

namespace itp::qp {

template <typename S>
struct RayCheck {
  S residual = S(0);  // |A'y_rows + y_bounds|_inf, y normalised
  S gap = S(0);       // -support(y), y normalised (> 0 for a certificate)
  bool holds = false;
};

template <class D>
RayCheck<typename D::Scalar> check_dual_ray(const QpProblem<D>& p, const typename D::Scalar* y_bounds,
                                            const typename D::Scalar* y_rows, typename D::Scalar radius) {
  using S = typename D::Scalar;
  RayCheck<S> out;
  // Normalisation: largest |y_c| |a_c| (bounds have |a| = 1).
  S ymax = S(0);
  for (int j = 0; j < p.n; ++j) {
    const S w = std::abs(y_bounds[j]);
    if (!(w <= ymax)) ymax = w;
  }
  for (int r = 0; r < p.m; ++r) {
    if (y_rows[r] == S(0)) continue;
    const S w = std::abs(y_rows[r]) / rows::row_inverse_norm(p.a_val[r], p.a_nnz[r]);
    if (!(w <= ymax)) ymax = w;
  }
  if (!(ymax > S(0)) || !(ymax < std::numeric_limits<S>::infinity())) return out;
  const S inv = S(1) / ymax;
  // r = A'y + y_bounds (normalised) and sum_c |y_c a_cj|, in stack arrays of N.
  S resid[static_cast<std::size_t>(D::kMaxVariables)];
  S absum[static_cast<std::size_t>(D::kMaxVariables)];
  S support = S(0), bound_scale = S(0);
  int terms = 0;
  for (int j = 0; j < p.n; ++j) {
    const S y = y_bounds[j] * inv;
    resid[j] = y;
    absum[j] = std::abs(y);
    if (y == S(0)) continue;
    ++terms;
    const S b = y > S(0) ? p.ub[j] : p.lb[j];
    support += y * b;
    if (!(std::abs(b) <= bound_scale)) bound_scale = std::abs(b);
  }
  for (int r = 0; r < p.m; ++r) {
    const S y = y_rows[r] * inv;
    if (y == S(0)) continue;
    ++terms;
    for (int k = 0; k < p.a_nnz[r]; ++k) {
      const S t = y * p.a_val[r][k];
      resid[p.a_col[r][k]] += t;
      absum[p.a_col[r][k]] += std::abs(t);
    }
    const S b = y > S(0) ? p.uba[r] : p.lba[r];
    support += y * b;
    const S bn = std::abs(b) * rows::row_inverse_norm(p.a_val[r], p.a_nnz[r]);
    if (!(bn <= bound_scale)) bound_scale = bn;
  }
  const S inf = std::numeric_limits<S>::infinity();
  S support_abs = S(0);
  for (int j = 0; j < p.n; ++j) {
    const S y = y_bounds[j] * inv;
    if (y != S(0)) support_abs += std::abs(y * (y > S(0) ? p.ub[j] : p.lb[j]));
    if (p.lb[j] > -inf && !(std::abs(p.lb[j]) <= bound_scale)) bound_scale = std::abs(p.lb[j]);
    if (p.ub[j] < inf && !(std::abs(p.ub[j]) <= bound_scale)) bound_scale = std::abs(p.ub[j]);
  }
  for (int r = 0; r < p.m; ++r) {
    const S y = y_rows[r] * inv;
    if (y != S(0)) support_abs += std::abs(y * (y > S(0) ? p.uba[r] : p.lba[r]));
  }
  const S far = radius * (S(1) + bound_scale);
  const S rounding = static_cast<S>(terms + 2) * std::numeric_limits<S>::epsilon();
  S rmax = S(0), reach = rounding * support_abs;
  for (int j = 0; j < p.n; ++j) {
    const S a = std::abs(resid[j]);
    if (!(a <= rmax)) rmax = a;
    const bool boxed = p.lb[j] > -inf && p.ub[j] < inf;
    const S xj = boxed ? (std::abs(p.lb[j]) > std::abs(p.ub[j]) ? std::abs(p.lb[j]) : std::abs(p.ub[j])) : far;
    reach += (a + rounding * absum[j]) * xj;
  }
  out.residual = rmax;
  out.gap = -support;
  // NaN or an infinite bound on a side the ray uses fails every comparison.
  out.holds = out.gap > S(0) && out.gap < inf && reach < out.gap;
  return out;
}

}  // namespace itp::qp
