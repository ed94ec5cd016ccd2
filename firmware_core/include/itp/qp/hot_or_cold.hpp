#pragma once
// The planner's QPs keep H and A from solve to solve while only g and the
// bounds change: they hotstart from the previous factorisation when the caller
// says the matrices are the same, and fall back to a cold solve otherwise.
#include "itp/qp/solver.hpp"

namespace itp::qp {

// `same_matrices`: H and A equal those of the previous usable solve with `ws`.
// Returns the status; `factor_valid` tells the caller whether the next call
// may hotstart (only after an optimal solve).
template <class D>
QpStatus solve_hot_or_cold(const QpProblem<D>& problem, QpWorkspace<D>& ws,
                           const QpSettings<typename D::Scalar>& settings, QpResult<D>& result,
                           bool same_matrices, bool& factor_valid) {
  QpStatus st = QpStatus::kNotFactored;
  if (same_matrices && factor_valid) {
    st = solve_hot(problem, ws, settings, result);
  }
  if (st == QpStatus::kNotFactored) {
    st = solve_cold(problem, ws, settings, result);
  }
  factor_valid = is_usable(st);
  return st;
}

}  // namespace itp::qp
