#pragma once
// Dual active-set QP solver (DAQP-style, Arnstroem, Bemporad, Axehill 2022)
// on a banded Hessian and a row-sparse constraint matrix. docs/qp.md has the
// derivation; in short, with H = L L' (banded) and x_unc = -H^-1 g:
//
//   u = L'(x - x_unc),   m_c = L^-1 a_c,   d_c = b_c - a_c' x_unc
//   min 1/2 |u|^2  s.t.  sigma_c m_c' u <= sigma_c d_c    (sigma: active side)
//
// The dual iterate lambda >= 0 lives on the working set W; the primal is
// u = -M_W' lambda. Each iteration either adds the most violated constraint
// or removes a blocking one; the Gram matrix K = M_W M_W' is kept as LDL' by
// rank-one updates (ldl_update.hpp). A constraint that is linearly dependent
// on W gives a null vector p of K: stepping lambda along p is a dual ray,
// and with no blocking component the QP is primal infeasible.
//
// Entry points: solve_cold, solve_warm (from a given working set) and
// solve_hot (same H and A as the previous solve, new g and bounds: reuses the
// factor of H, the rows of M and the factor of K).
#include <cmath>
#include <limits>

#include "itp/qp/banded_cholesky.hpp"
#include "itp/qp/dimensions.hpp"
#include "itp/qp/ldl_update.hpp"
#include "itp/qp/problem.hpp"
#include "itp/qp/status.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp {

namespace detail {

template <class D>
struct ActiveSetSolver {
  using S = typename D::Scalar;
  using Problem = QpProblem<D>;
  using Workspace = QpWorkspace<D>;
  static constexpr int kN = D::kMaxVariables;
  static constexpr int kA = D::kMaxActive;
  static constexpr int kC = D::kMaxConstraints;
  static constexpr int kBw = D::kBandwidth;
  static constexpr int kScanBlock = Workspace::kScanBlock;
  static constexpr int kScanBlockShift = Workspace::kScanBlockShift;
  using BlockIndex = typename Workspace::BlockIndex;

  const Problem& p;
  Workspace& ws;
  const QpSettings<S>& s;

  static bool is_bound(int c) { return c < kN; }

  S lower(int c) const { return is_bound(c) ? p.lb[c] : p.lba[c - kN]; }
  S upper(int c) const { return is_bound(c) ? p.ub[c] : p.uba[c - kN]; }
  bool is_equality(int c) const { return lower(c) == upper(c); }

  // a_c' v
  S dot_a(int c, const S* v) const { return is_bound(c) ? v[c] : p.row_dot(c - kN, v); }

  // d_c for the active side, signed: sigma (b_side - a_c' x_unc).
  S signed_rhs(int c, int side) const {
    const S b = side > 0 ? upper(c) : lower(c);
    return static_cast<S>(side) * (b - dot_a(c, ws.x_unc));
  }

  // Computes sigma L^-1 a_c into slot; returns |m|^2.
  S build_row(int c, int side, int slot) {
    S* row = ws.m_rows[slot];
    for (int j = 0; j < p.n; ++j) row[j] = S(0);
    int start;
    if (is_bound(c)) {
      row[c] = S(1);
      start = c;
    } else {
      const int r = c - kN;
      start = p.a_nnz[r] > 0 ? p.a_col[r][0] : p.n;
      for (int k = 0; k < p.a_nnz[r]; ++k) row[p.a_col[r][k]] = p.a_val[r][k];
    }
    band::forward_solve(ws.chol, p.n, row, start);
    S norm2 = S(0);
    const S sg = static_cast<S>(side);
    for (int j = start; j < p.n; ++j) {
      row[j] *= sg;
      norm2 += row[j] * row[j];
    }
    ws.m_start[slot] = static_cast<std::int16_t>(start);
    return norm2;
  }

  // Dense dot product from `from` to n with four partial sums (breaks the
  // floating-point dependency chain; the order is fixed, so still deterministic).
  S dense_dot(const S* a, const S* b, int from) const {
    S s0 = S(0), s1 = S(0), s2 = S(0), s3 = S(0);
    int j = from;
    for (; j + 3 < p.n; j += 4) {
      s0 += a[j] * b[j];
      s1 += a[j + 1] * b[j + 1];
      s2 += a[j + 2] * b[j + 2];
      s3 += a[j + 3] * b[j + 3];
    }
    for (; j < p.n; ++j) s0 += a[j] * b[j];
    return (s0 + s1) + (s2 + s3);
  }

  S row_dot(int slot_a, int slot_b) const {
    const int a = ws.m_start[slot_a], b = ws.m_start[slot_b];
    return dense_dot(ws.m_rows[slot_a], ws.m_rows[slot_b], a > b ? a : b);
  }

  // Factors position k (its slot already filled) against positions 0..k-1.
  // Returns true if the row is linearly independent of them.
  bool factor_position(int k, S norm2) {
    const int slot = ws.slot_of[k];
    for (int i = 0; i < k; ++i) ws.scratch[i] = row_dot(ws.slot_of[i], slot);
    const S pivot = ldl::append(ws.ldl_l, ws.ldl_d, k, ws.scratch, norm2);
    return k < p.n && pivot > s.singular_tolerance * norm2;
  }

  void reset_working_set() {
    ws.w_size = 0;
    ws.last_singular = false;
    ws.free_count = kA;
    for (int i = 0; i < kA; ++i) ws.free_slots[i] = static_cast<std::int16_t>(kA - 1 - i);
    for (int c = 0; c < kC; ++c) ws.active_side[c] = 0;
  }

  // Appends constraint c at `side`; sets last_singular if it is dependent.
  void add(int c, int side) {
    const int k = ws.w_size;
    const int slot = ws.free_slots[--ws.free_count];
    ws.slot_of[k] = static_cast<std::int16_t>(slot);
    ws.w_index[k] = static_cast<std::int16_t>(c);
    ws.w_side[k] = static_cast<std::int8_t>(side);
    ws.active_side[c] = static_cast<std::int8_t>(side);
    ws.lambda[k] = S(0);
    ws.d_w[k] = signed_rhs(c, side);
    const S norm2 = build_row(c, side, slot);
    ws.w_size = k + 1;
    ws.last_singular = !factor_position(k, norm2);
  }

  // Removes working-set position r.
  void remove(int r) {
    const int w = ws.w_size;
    ldl::remove(ws.ldl_l, ws.ldl_d, w, r, ws.scratch);
    ws.active_side[ws.w_index[r]] = 0;
    ws.free_slots[ws.free_count++] = ws.slot_of[r];
    for (int i = r; i + 1 < w; ++i) {
      ws.w_index[i] = ws.w_index[i + 1];
      ws.w_side[i] = ws.w_side[i + 1];
      ws.slot_of[i] = ws.slot_of[i + 1];
      ws.lambda[i] = ws.lambda[i + 1];
      ws.lambda_star[i] = ws.lambda_star[i + 1];
      ws.d_w[i] = ws.d_w[i + 1];
    }
    ws.w_size = w - 1;
    if (ws.last_singular && ws.w_size > 0) {
      // The dependent row is still last; the update recomputed its pivot.
      const int last = ws.w_size - 1;
      const int slot = ws.slot_of[last];
      const S norm2 = row_dot(slot, slot);
      ws.last_singular =
          !(last < p.n && ws.ldl_d[last] > s.singular_tolerance * norm2);
    } else if (ws.w_size == 0) {
      ws.last_singular = false;
    }
  }

  // Recomputes rows of M and the LDL' of K from scratch in the current order,
  // dropping rows that turn out to be dependent (except a dependent last row).
  void refactor() {
    const int w = ws.w_size;
    const bool had_singular = ws.last_singular;
    int k = 0;
    for (int i = 0; i < w; ++i) {
      const int c = ws.w_index[i];
      const int side = ws.w_side[i];
      const int slot = ws.slot_of[i];
      ws.w_index[k] = ws.w_index[i];
      ws.w_side[k] = ws.w_side[i];
      ws.slot_of[k] = ws.slot_of[i];
      ws.lambda[k] = ws.lambda[i];
      ws.d_w[k] = signed_rhs(c, side);
      const S norm2 = build_row(c, side, slot);
      const bool independent = factor_position(k, norm2);
      if (independent || (i == w - 1 && had_singular)) {
        ++k;
      } else {
        ws.active_side[c] = 0;
        ws.free_slots[ws.free_count++] = static_cast<std::int16_t>(slot);
      }
    }
    ws.w_size = k;
    ws.last_singular = false;
    if (k > 0 && had_singular && ws.w_index[k - 1] == ws.w_index[w - 1]) {
      const int slot = ws.slot_of[k - 1];
      const S norm2 = row_dot(slot, slot);
      ws.last_singular = !(k - 1 < p.n && ws.ldl_d[k - 1] > s.singular_tolerance * norm2);
    }
  }

  // x = L^-T u + x_unc with u = -M_W' lambda.
  void primal_from_dual() {
    for (int j = 0; j < p.n; ++j) ws.u[j] = S(0);
    for (int i = 0; i < ws.w_size; ++i) {
      const S li = ws.lambda[i];
      if (li == S(0)) continue;
      const int slot = ws.slot_of[i];
      const S* row = ws.m_rows[slot];
      for (int j = ws.m_start[slot]; j < p.n; ++j) ws.u[j] -= li * row[j];
    }
    S* xn = ws.scratch2;  // N + 1 >= n entries
    for (int j = 0; j < p.n; ++j) xn[j] = ws.u[j];
    band::backward_solve(ws.chol, p.n, xn);
    for (int j = 0; j < p.n; ++j) xn[j] += ws.x_unc[j];
    // Path length of this step per block of variables (for the scan's
    // row-skipping bound), rounded up so that it bounds the exact length.
    const S inflate = S(1) + S(64) * std::numeric_limits<S>::epsilon();
    const int nb = (p.n + kScanBlock - 1) >> kScanBlockShift;
    for (int b = 0; b < nb; ++b) {
      const int j0 = b << kScanBlockShift;
      const int j1 = j0 + kScanBlock < p.n ? j0 + kScanBlock : p.n;
      S s2 = S(0);
      for (int j = j0; j < j1; ++j) {
        const S dx = xn[j] - ws.x[j];
        s2 += dx * dx;
        ws.x[j] = xn[j];
      }
      ws.path_len[b] += std::sqrt(s2) * inflate;
    }
  }

  // Forgets every row's slack certificate (start of a solve: x, bounds or A
  // may have changed), so that the first scan evaluates all rows.
  void reset_scan_bookkeeping() {
    for (int r = 0; r < p.m; ++r) ws.row_cert[r] = -std::numeric_limits<S>::infinity();
    for (int b = 0; b < Workspace::kScanBlocks; ++b) ws.path_len[b] = S(0);
  }

  // Most violated inactive constraint (violation scaled by 1/|a_c|), or -1;
  // with `bland`, the lowest-index violated constraint instead. This scan over
  // all m rows is the dominant O(m nnz) term of an iteration, so it is
  // written out flat: two partial sums per row, no per-row branches on the
  // bounds (an infinite bound gives a violation of -inf).
  //
  // Row skipping (same choice as the full scan): when a row is evaluated, its
  // scaled slack sl = min(ub - a'x, a'x - lb)/|a| minus a bound of its
  // rounding error is stored together with the path length P_r that x has
  // travelled so far in the blocks of variables the row touches. Since
  // |a'(x' - x)|/|a| <= |x' - x| restricted to those columns <= growth of P_r
  // (triangle inequality over the steps), the row's true slack now is at least
  // row_cert - P_r(now). Above 2 primal_tolerance the row's computed violation
  // cannot exceed primal_tolerance, so it could never be selected: skip it.
  // NaN anywhere makes the test false and the row is evaluated.
  int most_violated(bool bland, int* side_out) {
    int best = -1;
    S best_v = s.primal_tolerance;
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
    const S threshold = S(2) * s.primal_tolerance + S(16) * eps * pre[nb];
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
      }
    }
    *side_out = best_side;
    return best;
  }

  // Largest relative residual |m_i'u - d_i| / (1 + |d_i|) over W.
  S active_residual() const {
    S worst = S(0);
    for (int i = 0; i < ws.w_size; ++i) {
      const int slot = ws.slot_of[i];
      const S* row = ws.m_rows[slot];
      const S mu = dense_dot(row, ws.u, ws.m_start[slot]);
      const S r = std::abs(mu - ws.d_w[i]) / (S(1) + std::abs(ws.d_w[i]));
      if (!(r <= worst)) worst = r;  // NaN-propagating max
    }
    return worst;
  }

  // Each pass of the loop either stops, refactorises (at most
  // kMaxRefactorisations times) or changes the working set (counted; at most
  // max_iterations times), so the loop is bounded by kMaxPasses.
  static constexpr int kMaxPasses = D::kMaxIterations + D::kMaxRefactorisations + 1;

  QpStatus iterate(int max_iterations, QpResult<D>& res) {
    int zero_steps = 0;
    int& it = res.iterations;
    for (int pass = 0; pass < kMaxPasses; ++pass) {
      const bool bland = zero_steps > D::kMaxZeroSteps;
      const int w = ws.w_size;
      if (!ws.last_singular) {
        // lambda* = -K^-1 d_W: multipliers of the equality QP on W.
        for (int i = 0; i < w; ++i) ws.lambda_star[i] = -ws.d_w[i];
        ldl::solve(ws.ldl_l, ws.ldl_d, w, ws.lambda_star);
        int block = -1;
        S best = S(0);
        for (int i = 0; i < w; ++i) {
          if (is_equality(ws.w_index[i]) || !(ws.lambda_star[i] < -s.dual_tolerance)) {
            continue;
          }
          const S ratio = ws.lambda[i] / (ws.lambda[i] - ws.lambda_star[i]);
          if (block < 0 || ratio < best ||
              (ratio == best && ws.w_index[i] < ws.w_index[block])) {
            block = i;
            best = ratio;
          }
        }
        if (block < 0) {
          for (int i = 0; i < w; ++i) {
            const S l = ws.lambda_star[i];
            ws.lambda[i] = (l < S(0) && !is_equality(ws.w_index[i])) ? S(0) : l;
          }
          primal_from_dual();
          int side = 0;
          const int c = most_violated(bland, &side);
          if (c < 0) {
            const S resid = active_residual();
            if (!(resid <= s.refactor_tolerance) &&
                res.refactorisations < D::kMaxRefactorisations) {
              ++res.refactorisations;
              refactor();
              continue;
            }
            return QpStatus::kOptimal;
          }
          if (it >= max_iterations || ws.w_size >= kA) return QpStatus::kIterationLimit;
          add(c, side);
          ++it;
          zero_steps = 0;
        } else {
          if (it >= max_iterations) return QpStatus::kIterationLimit;
          for (int i = 0; i < w; ++i) {
            ws.lambda[i] += best * (ws.lambda_star[i] - ws.lambda[i]);
          }
          ws.lambda[block] = S(0);
          remove(block);
          ++it;
          zero_steps = best > S(0) ? 0 : zero_steps + 1;
        }
      } else {
        // Dependent last row: p with M_W' p = 0, p_last = 1, is a direction of
        // dual ascent (it raises the violated constraint's multiplier without
        // moving u). Step until an inequality multiplier reaches zero.
        S* dir = ws.scratch;
        ldl::null_vector(ws.ldl_l, w, dir);
        S pmax = S(0);
        for (int i = 0; i < w; ++i) pmax = std::abs(dir[i]) > pmax ? std::abs(dir[i]) : pmax;
        const S ptol = S(64) * std::numeric_limits<S>::epsilon() * pmax;
        int block = -1;
        S best = S(0);
        for (int i = 0; i + 1 < w; ++i) {
          if (is_equality(ws.w_index[i]) || !(dir[i] < -ptol)) continue;
          const S ratio = ws.lambda[i] / -dir[i];
          if (block < 0 || ratio < best ||
              (ratio == best && ws.w_index[i] < ws.w_index[block])) {
            block = i;
            best = ratio;
          }
        }
        if (block < 0) return QpStatus::kInfeasible;
        if (it >= max_iterations) return QpStatus::kIterationLimit;
        for (int i = 0; i < w; ++i) ws.lambda[i] += best * dir[i];
        ws.lambda[block] = S(0);
        remove(block);
        ++it;
        zero_steps = best > S(0) ? 0 : zero_steps + 1;
      }
    }
    return QpStatus::kIterationLimit;
  }

  void write_result(QpStatus status, QpResult<D>& res) {
    res.status = status;
    for (int j = 0; j < p.n; ++j) {
      res.x[j] = ws.x[j];
      res.y_bounds[j] = S(0);
    }
    for (int r = 0; r < p.m; ++r) res.y_rows[r] = S(0);
    res.working_set.clear();
    const int w = ws.w_size - (ws.last_singular ? 1 : 0);
    for (int i = 0; i < w; ++i) {
      const int c = ws.w_index[i];
      const S y = static_cast<S>(ws.w_side[i]) * ws.lambda[i];
      if (is_bound(c)) {
        res.y_bounds[c] = y;
      } else {
        res.y_rows[c - kN] = y;
      }
      (void)res.working_set.push(is_bound(c) ? c : c - kN, is_bound(c), ws.w_side[i]);
    }
    // objective = 1/2 x'Hx + g'x
    band::multiply(p.h_band, p.n, ws.x, ws.scratch2);
    S obj = S(0);
    for (int j = 0; j < p.n; ++j) obj += ws.x[j] * (S(0.5) * ws.scratch2[j] + p.g[j]);
    res.objective = obj;
  }

  enum class Start { kCold, kWarm, kHot };

  QpStatus run(Start start, const WorkingSet<D>* warm, QpResult<D>& res) {
    res.iterations = 0;
    res.refactorisations = 0;
    if (!is_valid(p)) {
      res.status = QpStatus::kInvalidInput;
      return res.status;
    }
    if (start == Start::kHot) {
      if (!ws.factored || ws.factored_n != p.n || ws.factored_m != p.m) {
        res.status = QpStatus::kNotFactored;
        return res.status;
      }
    } else {
      ws.factored = false;
      if (!band::cholesky(p.h_band, ws.chol, p.n, s.regularisation)) {
        res.status = QpStatus::kNotConvex;
        return res.status;
      }
      for (int j = 0; j < kN; ++j) ws.row_scale[j] = S(1);
      for (int r = 0; r < p.m; ++r) {
        S n2 = S(0);
        for (int k = 0; k < p.a_nnz[r]; ++k) n2 += p.a_val[r][k] * p.a_val[r][k];
        ws.row_scale[kN + r] = n2 > S(0) ? S(1) / std::sqrt(n2) : S(1);
        const int nnz = p.a_nnz[r];
        ws.row_first_block[r] =
            static_cast<BlockIndex>(nnz > 0 ? p.a_col[r][0] >> kScanBlockShift : 0);
        ws.row_end_block[r] =
            static_cast<BlockIndex>(nnz > 0 ? (p.a_col[r][nnz - 1] >> kScanBlockShift) + 1 : 0);
      }
      reset_working_set();
      ws.factored = true;
      ws.factored_n = p.n;
      ws.factored_m = p.m;
    }
    // x_unc = -H^-1 g
    for (int j = 0; j < p.n; ++j) ws.x_unc[j] = -p.g[j];
    band::forward_solve(ws.chol, p.n, ws.x_unc, 0);
    band::backward_solve(ws.chol, p.n, ws.x_unc);

    if (start == Start::kWarm && warm != nullptr) {
      const int count = warm->size < kA ? warm->size : kA;
      for (int e = 0; e < count; ++e) {
        const ActiveConstraint& a = warm->entries[e];
        const int c = a.is_bound ? a.index : kN + a.index;
        const bool in_range = a.is_bound ? (a.index >= 0 && a.index < p.n)
                                         : (a.index >= 0 && a.index < p.m);
        if (!in_range || ws.active_side[c] != 0 || ws.w_size >= p.n) continue;
        const int side = a.side < 0 ? -1 : 1;
        if (!std::isfinite(side > 0 ? upper(c) : lower(c))) continue;
        add(c, side);
        if (ws.last_singular) remove(ws.w_size - 1);
      }
    } else if (start == Start::kHot) {
      if (ws.last_singular) remove(ws.w_size - 1);
      // Bounds may have changed: refresh d_W, drop entries whose side is gone.
      for (int i = ws.w_size - 1; i >= 0; --i) {
        const int c = ws.w_index[i];
        if (!std::isfinite(ws.w_side[i] > 0 ? upper(c) : lower(c))) remove(i);
      }
      for (int i = 0; i < ws.w_size; ++i) {
        ws.d_w[i] = signed_rhs(ws.w_index[i], ws.w_side[i]);
      }
    }
    for (int i = 0; i < ws.w_size; ++i) ws.lambda[i] = S(0);
    for (int j = 0; j < p.n; ++j) ws.x[j] = ws.x_unc[j];
    reset_scan_bookkeeping();

    const int cap = (s.max_iterations > 0 && s.max_iterations < D::kMaxIterations)
                        ? s.max_iterations
                        : D::kMaxIterations;
    const QpStatus status = iterate(cap, res);
    write_result(status, res);
    return status;
  }
};

}  // namespace detail

// Cold start: factorises H, starts from the unconstrained optimum, W = {}.
template <class D>
QpStatus solve_cold(const QpProblem<D>& problem, QpWorkspace<D>& ws,
                    const QpSettings<typename D::Scalar>& settings, QpResult<D>& result) {
  detail::ActiveSetSolver<D> solver{problem, ws, settings};
  return solver.run(detail::ActiveSetSolver<D>::Start::kCold, nullptr, result);
}

// Warm start: factorises H, then builds W from `working_set` (entries that are
// out of range, duplicated, unbounded on their side or linearly dependent are
// skipped). Multipliers start at zero, so any working set is a valid start.
template <class D>
QpStatus solve_warm(const QpProblem<D>& problem, QpWorkspace<D>& ws,
                    const QpSettings<typename D::Scalar>& settings,
                    const WorkingSet<D>& working_set, QpResult<D>& result) {
  detail::ActiveSetSolver<D> solver{problem, ws, settings};
  return solver.run(detail::ActiveSetSolver<D>::Start::kWarm, &working_set, result);
}

// Hotstart: H, A, n and m must equal those of the previous solve with this
// workspace (only g, lb, ub, lbA, ubA may change). Reuses the factor of H,
// the rows of M and the factor of K from the previous final working set.
// Returns kNotFactored if the workspace holds no factorisation for n, m.
template <class D>
QpStatus solve_hot(const QpProblem<D>& problem, QpWorkspace<D>& ws,
                   const QpSettings<typename D::Scalar>& settings, QpResult<D>& result) {
  detail::ActiveSetSolver<D> solver{problem, ws, settings};
  return solver.run(detail::ActiveSetSolver<D>::Start::kHot, nullptr, result);
}

}  // namespace itp::qp
