#pragma once
// Entry points of the dual active-set QP solver (docs/qp.md): solve_cold,
// solve_warm (from a given working set) and solve_hot (same H and A as the
// previous solve, new g and bounds: reuses the factor of H, the rows of M and
// the factor of K). The loop itself is active_set.hpp; a singular H adds the
// proximal-point iterations of proximal.hpp around it.
//
// Statuses are trustworthy by construction: kOptimal only after x passed a
// feasibility and finiteness check, kInfeasible only with a checked dual ray,
// kNotConvex only with a direction of negative curvature; what the arithmetic
// cannot settle is kNumericalTrouble.
#include <cmath>
#include <limits>

#include "itp/qp/active_set.hpp"
#include "itp/qp/banded_cholesky.hpp"
#include "itp/qp/dimensions.hpp"
#include "itp/qp/hessian_factor.hpp"
#include "itp/qp/problem.hpp"
#include "itp/qp/proximal.hpp"
#include "itp/qp/row_scaling.hpp"
#include "itp/qp/status.hpp"
#include "itp/qp/violation_scan.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp {

namespace detail {

enum class Start { kCold, kWarm, kHot };

template <class D>
struct SolveRun : ActiveSetSolver<D> {
  using Base = ActiveSetSolver<D>;
  using S = typename D::Scalar;
  using typename Base::BlockIndex;
  using Base::kA;
  using Base::kN;
  using Base::kScanBlockShift;
  using Base::p;
  using Base::s;
  using Base::ws;

  // Factor of H (or H + eps I), row scales and block ranges: whenever H or A
  // may have changed (cold and warm starts). sum_sq: each row's sum of
  // squares (rows_valid, during validation).
  QpStatus factor(const S* sum_sq) {
    ws.factored = false;
    ws.chain_stride = 0;
    ws.even_band = false;
    S weight = S(0);
    const HessianKind kind = factor_hessian(p, ws, s.proximal_weight, weight);
    if (kind == HessianKind::kNegativeCurvature) return QpStatus::kNotConvex;
    if (kind == HessianKind::kFailed) return QpStatus::kNumericalTrouble;
    ws.proximal_weight = weight;
    ws.even_band = band::odd_offsets_zero(p.h_band, p.n);
    for (int j = 0; j < kN; ++j) ws.row_scale[j] = S(1);
    for (int r = 0; r < p.m; ++r) {
      ws.row_scale[kN + r] = rows::inverse_norm_of_sum(sum_sq[r], p.a_val[r], p.a_nnz[r]);
      const int nnz = p.a_nnz[r];
      ws.row_first_block[r] =
          static_cast<BlockIndex>(nnz > 0 ? p.a_col[r][0] >> kScanBlockShift : 0);
      ws.row_end_block[r] =
          static_cast<BlockIndex>(nnz > 0 ? (p.a_col[r][nnz - 1] >> kScanBlockShift) + 1 : 0);
    }
    this->reset_working_set();
    ws.factored = true;
    ws.factored_n = p.n;
    ws.factored_m = p.m;
    return QpStatus::kOptimal;
  }

  // x_unc = -H^-1 g (positive definite H: exactly the old arithmetic), or the
  // proximal version around `centre`.
  void unconstrained(const S* centre) {
    if (ws.proximal_weight > S(0)) {
      prox::unconstrained_optimum(p, ws, centre);
      return;
    }
    for (int j = 0; j < p.n; ++j) ws.x_unc[j] = -p.g[j];
    band::forward_solve(ws.chol, p.n, ws.x_unc, 0);
    band::backward_solve(ws.chol, p.n, ws.x_unc);
  }

  // Bounds (or x_unc) changed with W kept: refresh d_W, drop entries whose
  // side has become infinite.
  void refresh_working_set() {
    if (ws.last_singular) this->remove(ws.w_size - 1);
    for (int i = ws.w_size - 1; i >= 0; --i) {
      const int c = ws.w_index[i];
      if (!std::isfinite(ws.w_side[i] > 0 ? this->upper(c) : this->lower(c))) this->remove(i);
    }
    for (int i = 0; i < ws.w_size; ++i) {
      ws.d_w[i] = this->signed_rhs(ws.w_index[i], ws.w_side[i]);
    }
    ws.fwd_valid = 0;
  }

  void load_warm(const WorkingSet<D>& warm) {
    const int count = warm.size < kA ? warm.size : kA;
    for (int e = 0; e < count; ++e) {
      const ActiveConstraint& a = warm.entries[e];
      const int c = a.is_bound ? a.index : kN + a.index;
      const bool in_range = a.is_bound ? (a.index >= 0 && a.index < p.n)
                                       : (a.index >= 0 && a.index < p.m);
      if (!in_range || ws.active_side[c] != 0 || ws.w_size >= p.n) continue;
      const int side = a.side < 0 ? -1 : 1;
      if (!std::isfinite(side > 0 ? this->upper(c) : this->lower(c))) continue;
      this->add(c, side);
      if (ws.last_singular) this->remove(ws.w_size - 1);
    }
  }

  // Equality constraints (lb == ub) that x_unc violates enter W before the
  // first scan, as in DAQP: their multipliers are free, so the scan would
  // add each of them anyway, one pass over all rows apiece (the speed QP's
  // initial s, s', s'': three of a typical six iterations). Bounds first,
  // then rows, each on the side x_unc violates; a dependent one is left to
  // the loop. One that x_unc meets is left out: the scan adds it if a later
  // step violates it (a satisfied equality added ahead of an ill-conditioned
  // row can make that row look dependent, tests/qp/test_unscaled_feasibility).
  // Each counts as an iteration (a working-set change, costing less than a
  // scan and an add); none is added once `cap` is reached.
  void load_equalities(int cap, QpResult<D>& res) {
    for (int j = 0; j < p.n; ++j) {
      if (p.lb[j] == p.ub[j]) load_equality(j, p.lb[j], cap, res);
    }
    for (int r = 0; r < p.m; ++r) {
      if (p.lba[r] == p.uba[r]) load_equality(kN + r, p.lba[r], cap, res);
    }
  }

  // Equality constraint c = b (finite: validation rejects a lower bound of
  // +inf and an upper bound of -inf).
  void load_equality(int c, S b, int cap, QpResult<D>& res) {
    if (res.iterations >= cap || ws.w_size >= p.n || ws.active_side[c] != 0) return;
    const S excess = this->dot_a(c, ws.x_unc) - b;
    if (!(std::abs(excess) * ws.row_scale[c] > s.primal_tolerance)) return;
    this->add(c, excess > S(0) ? 1 : -1);
    if (ws.last_singular) {
      this->remove(ws.w_size - 1);
      return;
    }
    ++res.iterations;
  }

  // One inner solve from the current W with multipliers 0 and x = x_unc.
  QpStatus inner_solve(int cap, QpResult<D>& res) {
    this->clear_set_aside();
    for (int i = 0; i < ws.w_size; ++i) ws.lambda[i] = S(0);
    for (int j = 0; j < p.n; ++j) ws.x[j] = ws.x_unc[j];
    scan::reset_bookkeeping(p, ws);
    return this->iterate(cap, res);
  }

  // Proximal-point iterations (proximal.hpp) after the first inner solve.
  // res.x holds the centre x_k (it is overwritten by the result at the end).
  QpStatus proximal_loop(QpStatus status, int cap, QpResult<D>& res) {
    const int steps = (s.max_proximal_steps > 0 && s.max_proximal_steps < D::kMaxProximalSteps)
                          ? s.max_proximal_steps
                          : D::kMaxProximalSteps;
    int before = 0;
    for (int k = 0; k < steps && status == QpStatus::kOptimal; ++k) {
      const bool steady = k > 0 && res.iterations == before;
      const prox::StepVerdict verdict = prox::judge_step(p, ws, s, res.x, steady);
      if (verdict == prox::StepVerdict::kConverged) return QpStatus::kOptimal;
      if (verdict == prox::StepVerdict::kNotConvex) return QpStatus::kNotConvex;
      if (verdict == prox::StepVerdict::kUnbounded) return QpStatus::kUnbounded;
      for (int j = 0; j < p.n; ++j) res.x[j] = ws.x[j];
      ++res.proximal_steps;
      before = res.iterations;
      unconstrained(res.x);
      refresh_working_set();
      status = inner_solve(cap, res);
    }
    return status == QpStatus::kOptimal ? QpStatus::kIterationLimit : status;
  }

  QpStatus run(Start start, const WorkingSet<D>* warm, QpResult<D>& res) {
    res.iterations = 0;
    res.refactorisations = 0;
    res.proximal_steps = 0;
    res.certificate_residual = S(0);
    res.certificate_gap = S(0);
    // A hotstart's H and A are those validated at the factorisation (the
    // documented precondition), so only its vectors are checked again. The
    // rows' sums of squares (for factor()'s row scales) go to row_cert, the
    // scan's bookkeeping, which every solve resets before its first scan.
    if (!(start == Start::kHot ? is_valid_vectors(p) : is_valid(p, ws.row_cert))) {
      res.status = QpStatus::kInvalidInput;
      return res.status;
    }
    if (start == Start::kHot) {
      if (!ws.factored || ws.factored_n != p.n || ws.factored_m != p.m) {
        res.status = QpStatus::kNotFactored;
        return res.status;
      }
    } else {
      const QpStatus st = factor(ws.row_cert);
      if (st != QpStatus::kOptimal) {
        res.status = st;
        return res.status;
      }
    }
    const bool proximal = ws.proximal_weight > S(0);
    if (proximal) {
      // The first centre: the previous solution for a hotstart (ws.x), else 0.
      for (int j = 0; j < p.n; ++j) {
        res.x[j] = (start == Start::kHot && std::isfinite(ws.x[j])) ? ws.x[j] : S(0);
      }
    }
    unconstrained(res.x);
    const int cap = (s.max_iterations > 0 && s.max_iterations < D::kMaxIterations)
                        ? s.max_iterations
                        : D::kMaxIterations;
    if (start == Start::kWarm && warm != nullptr) {
      load_warm(*warm);
    } else if (start == Start::kHot) {
      refresh_working_set();
    }
    if (start != Start::kHot) load_equalities(cap, res);
    QpStatus status = inner_solve(cap, res);
    if (proximal) status = proximal_loop(status, cap, res);
    this->write_result(status, res);
    this->clear_set_aside();
    if (status == QpStatus::kOptimal && !std::isfinite(res.objective)) {
      res.status = QpStatus::kNumericalTrouble;
    }
    return res.status;
  }
};

}  // namespace detail

// Cold start: factorises H, starts from the unconstrained optimum with W = the
// equalities it violates (SolveRun::load_equalities).
template <class D>
QpStatus solve_cold(const QpProblem<D>& problem, QpWorkspace<D>& ws,
                    const QpSettings<typename D::Scalar>& settings, QpResult<D>& result) {
  detail::SolveRun<D> solver{{problem, ws, settings}};
  return solver.run(detail::Start::kCold, nullptr, result);
}

// Warm start: factorises H, then builds W from `working_set` (entries that are
// out of range, duplicated, unbounded on their side or linearly dependent are
// skipped), then the equalities x_unc violates that it lacks. Multipliers
// start at zero, so any working set is a valid start.
template <class D>
QpStatus solve_warm(const QpProblem<D>& problem, QpWorkspace<D>& ws,
                    const QpSettings<typename D::Scalar>& settings,
                    const WorkingSet<D>& working_set, QpResult<D>& result) {
  detail::SolveRun<D> solver{{problem, ws, settings}};
  return solver.run(detail::Start::kWarm, &working_set, result);
}

// Hotstart: H, A, n and m must equal those of the previous solve with this
// workspace (only g, lb, ub, lbA, ubA may change). Reuses the factor of H,
// the rows of M and the factor of K from the previous final working set.
// Returns kNotFactored if the workspace holds no factorisation for n, m.
template <class D>
QpStatus solve_hot(const QpProblem<D>& problem, QpWorkspace<D>& ws,
                   const QpSettings<typename D::Scalar>& settings, QpResult<D>& result) {
  detail::SolveRun<D> solver{{problem, ws, settings}};
  return solver.run(detail::Start::kHot, nullptr, result);
}

}  // namespace itp::qp
