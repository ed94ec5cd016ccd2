#pragma once
// The violation scan: the most violated inactive constraint, the O(m nnz) term
// of every iteration of the dual active-set loop (active_set.hpp).
//
// Violations are ranked on rows scaled to unit 2-norm (row_scale = 1/|a|,
// row_scaling.hpp). With `bland`, the lowest-index violated constraint is
// taken instead (anti-cycling). The loop is flat: two partial sums per row,
// no per-row branches on the bounds (an infinite bound gives -inf).
//
// Row skipping (same choice as the full scan): when a row is evaluated, its
// scaled slack sl = min(ub - a'x, a'x - lb)/|a| minus a bound of its rounding
// error is stored together with the path length P_r that x has travelled so
// far in the blocks of variables the row touches. Since
// |a'(x' - x)|/|a| <= |x' - x| restricted to those columns <= growth of P_r
// (Cauchy-Schwarz, triangle inequality over the steps), the row's true slack
// now is at least row_cert - P_r(now). Above 2 primal_tolerance the row's
// computed violation cannot exceed primal_tolerance, so it could never be
// selected: skip it. NaN anywhere makes the test false and the row is
// evaluated. For a finite x, a NaN violation arises only from a'x = +-inf
// against an infinite bound of the same sign, which is satisfied, so a NaN
// never hides a violated row.
#include <cmath>
#include <cstdint>
#include <limits>

#include "itp/qp/problem.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp::scan {

// Forgets every row's slack certificate (start of a solve: x, bounds or A
// may have changed), so that the first scan evaluates all rows.
template <class D>
void reset_bookkeeping(const QpProblem<D>& p, QpWorkspace<D>& ws) {
  using S = typename D::Scalar;
  for (int r = 0; r < p.m; ++r) ws.row_cert[r] = -std::numeric_limits<S>::infinity();
  for (int b = 0; b < QpWorkspace<D>::kScanBlocks; ++b) ws.path_len[b] = S(0);
}

// A row that the unit-row test accepts although its violation breaks the
// unscaled contract (docs/qp.md, "Feasibility contract"):
//   v = max(a'x - ub, lb - a'x) > tolerance * max(1, sum_k |a_k x_k|, |b|)
// (b the bound on the violated side). The unit-row test alone lets a row of
// norm |a| be violated by primal_tolerance |a| whatever x and b are: 0.3 on a
// row of norm 1e9 at x = 0 (the fuzz finding of docs/fuzzing.md). Bounds
// never qualify: their test is absolute and primal_tolerance <= tolerance.
template <typename S>
struct UnscaledViolation {
  int constraint = -1;  // constraint id (rows N..), -1: none
  int side = 0;
  S relative = S(0);  // v / max(1, sum |a_k x_k|, |b|) of that row
};

// Most violated inactive constraint id (bounds 0..N-1, rows N..), or -1 if
// none is violated by more than primal_tolerance; its side in *side_out.
// If `unscaled` is given, it receives the row of largest relative violation
// among the evaluated rows that the unit-row test accepts but that violate the
// unscaled contract with `unscaled_tolerance`; complete whenever the function
// returns -1 (rows it skips have a certified positive slack; active and
// set-aside constraints are checked by the caller). The choice of the return
// value, the certificates and their arithmetic are those without `unscaled`.
template <class D>
int most_violated(const QpProblem<D>& p, QpWorkspace<D>& ws, typename D::Scalar primal_tolerance, bool bland,
                  int* side_out, typename D::Scalar unscaled_tolerance = typename D::Scalar(0),
                  UnscaledViolation<typename D::Scalar>* unscaled = nullptr) {
  using S = typename D::Scalar;
  using Workspace = QpWorkspace<D>;
  using BlockIndex = typename Workspace::BlockIndex;
  constexpr int kN = D::kMaxVariables;
  constexpr int kScanBlock = Workspace::kScanBlock;
  constexpr int kScanBlockShift = Workspace::kScanBlockShift;
  int best = -1;
  S best_v = primal_tolerance;
  int best_side = 0;
  if (unscaled != nullptr) *unscaled = UnscaledViolation<S>{};
  for (int j = 0; j < p.n; ++j) {
    if (ws.active_side[j] != 0) continue;
    const S up = ws.x[j] - p.ub[j];
    const S lo = p.lb[j] - ws.x[j];
    const S v = up > lo ? up : lo;
    if (v > best_v) {
      best = j;
      best_v = v;
      best_side = up > lo ? 1 : -1;
      if (bland) break;
    }
  }
  if (bland && best >= 0) {
    *side_out = best_side;
    return best;
  }
  const S eps = std::numeric_limits<S>::epsilon();
  S* pre = ws.path_prefix;
  const int nb = (p.n + kScanBlock - 1) >> kScanBlockShift;
  pre[0] = S(0);
  for (int b = 0; b < nb; ++b) pre[b + 1] = pre[b] + ws.path_len[b];
  // 2 primal_tolerance plus the rounding of the prefix-sum differences.
  const S threshold = S(2) * primal_tolerance + S(16) * eps * pre[nb];
  const std::int8_t* row_active = ws.active_side + kN;
  const BlockIndex* first_block = ws.row_first_block;
  const BlockIndex* end_block = ws.row_end_block;
  S* cert = ws.row_cert;
  for (int r = 0; r < p.m; ++r) {
    if (row_active[r] != 0) continue;
    const S travelled = pre[end_block[r]] - pre[first_block[r]];
    if (cert[r] - travelled > threshold) continue;
    const S* val = p.a_val[r];
    const std::int16_t* col = p.a_col[r];
    const int nnz = p.a_nnz[r];
    S s0 = S(0), s1 = S(0), t0 = S(0), t1 = S(0);
    int k = 0;
    for (; k + 1 < nnz; k += 2) {
      const S p0 = val[k] * ws.x[col[k]];
      const S p1 = val[k + 1] * ws.x[col[k + 1]];
      s0 += p0;
      s1 += p1;
      t0 += std::abs(p0);
      t1 += std::abs(p1);
    }
    if (k < nnz) {
      const S p0 = val[k] * ws.x[col[k]];
      s0 += p0;
      t0 += std::abs(p0);
    }
    const S ax = s0 + s1;
    const S up = ax - p.uba[r];
    const S lo = p.lba[r] - ax;
    const S scale = ws.row_scale[kN + r];
    const S v = (up > lo ? up : lo) * scale;
    // Certificate: slack -v minus a bound of its rounding error.
    const S b_near = up > lo ? p.uba[r] : p.lba[r];
    const S guard = static_cast<S>(2 * (nnz + 2)) * eps * (t0 + t1 + std::abs(b_near)) * scale;
    cert[r] = (-v - guard) + travelled;
    if (v > best_v) {
      best = kN + r;
      best_v = v;
      best_side = up > lo ? 1 : -1;
      if (bland) break;
    } else if (v > S(0) && unscaled != nullptr) {
      // Violated, but within primal_tolerance on the unit row (once no row
      // is violated beyond it, i.e. when it matters): the unscaled contract.
      S mag = t0 + t1;
      if (std::abs(b_near) > mag) mag = std::abs(b_near);
      if (mag < S(1)) mag = S(1);
      const S rel = (up > lo ? up : lo) / mag;
      if (rel > unscaled_tolerance && rel > unscaled->relative) {
        unscaled->constraint = kN + r;
        unscaled->side = up > lo ? 1 : -1;
        unscaled->relative = rel;
      }
    }
  }
  *side_out = best_side;
  return best;
}

}  // namespace itp::qp::scan
