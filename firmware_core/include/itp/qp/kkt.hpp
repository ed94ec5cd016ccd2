#pragma once
// Independent check of a QP solution: the KKT residuals of (x, y) in the
// sign convention  Hx + g + A'y_rows + y_bounds = 0,  y > 0 at an upper side,
// y < 0 at a lower side. It uses only the problem data, never solver state.
#include <cmath>
#include <cstddef>

#include "itp/qp/banded_cholesky.hpp"
#include "itp/qp/problem.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp {

template <typename S>
struct KktResidual {
  S stationarity = S(0);     // |Hx + g + A'y_rows + y_bounds|_inf
  S primal = S(0);           // max bound / row violation
  S dual_sign = S(0);        // max |y| on a side whose bound is infinite
  S complementarity = S(0);  // max |y_i| * distance of the i-th value to the side y selects
  S max() const {
    S m = stationarity;
    if (!(primal <= m)) m = primal;
    if (!(dual_sign <= m)) m = dual_sign;
    if (!(complementarity <= m)) m = complementarity;
    return m;
  }
};

namespace detail {
template <typename S>
void kkt_accumulate(S value, S lo, S hi, S y, KktResidual<S>& r) {
  const S viol = value > hi ? value - hi : (value < lo ? lo - value : S(0));
  if (!(viol <= r.primal)) r.primal = viol;
  const S ay = std::abs(y);
  if (y > S(0)) {
    if (!std::isfinite(hi)) {
      if (!(ay <= r.dual_sign)) r.dual_sign = ay;
    } else {
      const S c = ay * std::abs(hi - value);
      if (!(c <= r.complementarity)) r.complementarity = c;
    }
  } else if (y < S(0)) {
    if (!std::isfinite(lo)) {
      if (!(ay <= r.dual_sign)) r.dual_sign = ay;
    } else {
      const S c = ay * std::abs(value - lo);
      if (!(c <= r.complementarity)) r.complementarity = c;
    }
  }
}
}  // namespace detail

// Uses a stack array of kMaxVariables scalars.
template <class D>
KktResidual<typename D::Scalar> kkt_residual(const QpProblem<D>& p, const typename D::Scalar* x,
                                             const typename D::Scalar* y_bounds,
                                             const typename D::Scalar* y_rows) {
  using S = typename D::Scalar;
  KktResidual<S> r;
  S grad[static_cast<std::size_t>(D::kMaxVariables)];
  band::multiply(p.h_band, p.n, x, grad);
  for (int j = 0; j < p.n; ++j) grad[j] += p.g[j] + y_bounds[j];
  for (int i = 0; i < p.m; ++i) {
    for (int k = 0; k < p.a_nnz[i]; ++k) grad[p.a_col[i][k]] += p.a_val[i][k] * y_rows[i];
  }
  for (int j = 0; j < p.n; ++j) {
    const S a = std::abs(grad[j]);
    if (!(a <= r.stationarity)) r.stationarity = a;
  }
  for (int j = 0; j < p.n; ++j) detail::kkt_accumulate(x[j], p.lb[j], p.ub[j], y_bounds[j], r);
  for (int i = 0; i < p.m; ++i) {
    detail::kkt_accumulate(p.row_dot(i, x), p.lba[i], p.uba[i], y_rows[i], r);
  }
  return r;
}

template <class D>
KktResidual<typename D::Scalar> kkt_residual(const QpProblem<D>& p, const QpResult<D>& res) {
  return kkt_residual(p, res.x, res.y_bounds, res.y_rows);
}

}  // namespace itp::qp
