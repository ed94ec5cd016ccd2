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

// Most violated inactive constraint id (bounds 0..N-1, rows N..), or -1 if
// none is violated by more than primal_tolerance; its side in *side_out.
template <class D>
int most_violated(const QpProblem<D>& p, QpWorkspace<D>& ws, typename D::Scalar primal_tolerance, bool bland,
                  int* side_out) {
  using S = typename D::Scalar;
  using Workspace = QpWorkspace<D>;
  using BlockIndex = typename Workspace::BlockIndex;
  constexpr int kN = D::kMaxVariables;
  constexpr int kScanBlock = Workspace::kScanBlock;
  constexpr int kScanBlockShift = Workspace::kScanBlockShift;
  int best = -1;
  S best_v = primal_tolerance;
  int best_side = 0;
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
  // |x|_inf, NaN-propagating (a NaN makes every certificate NaN: no skips).
  S x_inf = S(0);
  for (int j = 0; j < p.n; ++j) {
    const S a = std::abs(ws.x[j]);
    if (!(a <= x_inf)) x_inf = a;
  }
  const std::int8_t* row_active = ws.active_side + kN;
  const BlockIndex* first_block = ws.row_first_block;
  const BlockIndex* end_block = ws.row_end_block;
  S* cert = ws.row_cert;
  for (int r = 0; r < p.m; ++r) {
    if (row_active[r] != 0) continue;
    const S travelled = pre[end_block[r]] - pre[first_block[r]];
    if (cert[r] - travelled > threshold) continue;
    const S* val = p.a_val[r];
    const typename D::ColumnIndex* col = p.a_col[r];
    const int nnz = p.a_nnz[r];
    S s0 = S(0), s1 = S(0);
    int k = 0;
    for (; k + 1 < nnz; k += 2) {
      s0 += val[k] * ws.x[col[k]];
      s1 += val[k + 1] * ws.x[col[k + 1]];
    }
    if (k < nnz) s0 += val[k] * ws.x[col[k]];
    const S ax = s0 + s1;
    const S up = ax - p.uba[r];
    const S lo = p.lba[r] - ax;
    const S scale = ws.row_scale[kN + r];
    const S v = (up > lo ? up : lo) * scale;
    // Certificate: slack -v minus a bound of its rounding error,
    // 2 (nnz + 2) eps (sum_k |a_k x_k| + |b|) / |a|, where
    // sum_k |a_k x_k| / |a| <= |a|_1 |x|_inf / |a|_2 <= sqrt(nnz) |x|_inf <= nnz |x|_inf
    // (row_scale is 1/|a| to a few ulps, well inside the factor 2 of 2 (nnz + 2)).
    const S b_near = up > lo ? p.uba[r] : p.lba[r];
    const S guard = static_cast<S>(2 * (nnz + 2)) * eps * (static_cast<S>(nnz) * x_inf + std::abs(b_near) * scale);
    cert[r] = (-v - guard) + travelled;
    if (v > best_v) {
      best = kN + r;
      best_v = v;
      best_side = up > lo ? 1 : -1;
      if (bland) break;
    }
  }
  *side_out = best_side;
  return best;
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

// The inactive row of largest relative violation v / max(1, sum |a_k x_k|, |b|)
// above `tolerance`, right after most_violated() returned -1 at this x (its
// certificates and prefix sums are those of this x). Only a row of norm above
// tolerance / primal_tolerance can pass the unit-row test (v <= primal_tolerance
// |a|) and still break the contract (v > tolerance, as max(1, ...) >= 1), so
// the others are skipped on their row_scale = 1/|a| alone; so is a row whose
// certificate proves a positive slack (row_cert - P_r > 0), and a row is
// summed only when v > tolerance. The scan of every iteration is unchanged;
// this costs one comparison per row per candidate optimum (and a certificate
// test for rows of large norm). Active and set-aside constraints are checked
// by the caller's final verification.
template <class D>
UnscaledViolation<typename D::Scalar> unscaled_violated(const QpProblem<D>& p, const QpWorkspace<D>& ws,
                                                        typename D::Scalar primal_tolerance,
                                                        typename D::Scalar tolerance) {
  using S = typename D::Scalar;
  constexpr int kN = D::kMaxVariables;
  UnscaledViolation<S> out;
  // Rows with 1/|a| >= primal_tolerance / tolerance cannot qualify.
  const S min_scale = primal_tolerance / tolerance;
  const S* pre = ws.path_prefix;
  const S* scale = ws.row_scale + kN;
  const std::int8_t* row_active = ws.active_side + kN;
  for (int r = 0; r < p.m; ++r) {
    if (scale[r] >= min_scale || row_active[r] != 0) continue;
    const S travelled = pre[ws.row_end_block[r]] - pre[ws.row_first_block[r]];
    if (ws.row_cert[r] - travelled > S(0)) continue;
    const S ax = p.row_dot(r, ws.x);
    const S up = ax - p.uba[r];
    const S lo = p.lba[r] - ax;
    const S v = up > lo ? up : lo;
    if (!(v > tolerance)) continue;
    S mag = S(0);
    for (int k = 0; k < p.a_nnz[r]; ++k) mag += std::abs(p.a_val[r][k] * ws.x[p.a_col[r][k]]);
    const S b = std::abs(up > lo ? p.uba[r] : p.lba[r]);
    if (b > mag) mag = b;
    if (mag < S(1)) mag = S(1);
    const S rel = v / mag;
    if (rel > tolerance && rel > out.relative) {
      out.constraint = kN + r;
      out.side = up > lo ? 1 : -1;
      out.relative = rel;
    }
  }
  return out;
}

}  // namespace itp::qp::scan
