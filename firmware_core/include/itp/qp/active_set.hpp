#pragma once
// The dual active-set loop (DAQP-style, Arnstroem, Bemporad, Axehill 2022) on
// a banded Hessian factor and a row-sparse constraint matrix. docs/qp.md has
// the derivation; in short, with H = L L' (banded; H + eps I for a singular H,
// proximal.hpp) and x_unc = -H^-1 g:
//
//   u = L'(x - x_unc),   m_c = L^-1 a_c,   d_c = b_c - a_c' x_unc
//   min 1/2 |u|^2  s.t.  sigma_c m_c' u <= sigma_c d_c    (sigma: active side)
//
// The dual iterate lambda >= 0 lives on the working set W; the primal is
// u = -M_W' lambda. Each iteration either adds the most violated constraint
// (violation_scan.hpp) or removes a blocking one; the Gram matrix K = M_W M_W'
// is kept as LDL' by rank-one updates (ldl_update.hpp). A constraint that is
// linearly dependent on W gives a null vector p of K: stepping lambda along p
// is a dual ray, and with no blocking component the QP is primal infeasible,
// once the ray passes its check (certificates.hpp).
//
// Rows whose norm lies outside [2^-E, 2^E] enter scaled by an exact power of
// two (row_scaling.hpp); all other rows see exactly the old arithmetic.
#include <algorithm>
#include <cmath>
#include <limits>

#include "itp/qp/banded_cholesky.hpp"
#include "itp/qp/certificates.hpp"
#include "itp/qp/dimensions.hpp"
#include "itp/qp/ldl_update.hpp"
#include "itp/qp/problem.hpp"
#include "itp/qp/row_scaling.hpp"
#include "itp/qp/status.hpp"
#include "itp/qp/violation_scan.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp::detail {

template <class D>
struct ActiveSetSolver {
  using S = typename D::Scalar;
  using Problem = QpProblem<D>;
  using Workspace = QpWorkspace<D>;
  static constexpr int kN = D::kMaxVariables;
  static constexpr int kA = D::kMaxActive;
  static constexpr int kC = D::kMaxConstraints;
  static constexpr int kScanBlock = Workspace::kScanBlock;
  static constexpr int kScanBlockShift = Workspace::kScanBlockShift;
  using BlockIndex = typename Workspace::BlockIndex;

  const Problem& p;
  Workspace& ws;
  const QpSettings<S>& s;

  // active_side value of a constraint set aside for the rest of the solve:
  // one whose violation is rounding of W, seen either as a dependent row whose
  // dual ray gives no ascent, or as a constraint that leaves again at once
  // with a zero step (a violated constraint enters with a positive multiplier
  // in exact arithmetic). Re-adding it would cycle. The scan skips it (side
  // != 0); primal_verified() checks it; clear_set_aside() ends the solve.
  static constexpr std::int8_t kSetAside = 2;

  static bool is_bound(int c) { return c < kN; }

  S lower(int c) const { return is_bound(c) ? p.lb[c] : p.lba[c - kN]; }
  S upper(int c) const { return is_bound(c) ? p.ub[c] : p.uba[c - kN]; }
  bool is_equality(int c) const { return lower(c) == upper(c); }

  // Exact power-of-two factor of constraint c in the transformed problem
  // (1 for every row of normal size, always for bounds).
  S row_power(int c) const { return is_bound(c) ? S(1) : rows::row_power(ws.row_scale[c]); }

  // a_c' v
  S dot_a(int c, const S* v) const { return is_bound(c) ? v[c] : p.row_dot(c - kN, v); }

  // d_c for the active side, signed and scaled: sigma pw (b_side - a_c' x_unc).
  S signed_rhs(int c, int side) const {
    const S b = side > 0 ? upper(c) : lower(c);
    const S pw = row_power(c);
    if (pw == S(1)) return static_cast<S>(side) * (b - dot_a(c, ws.x_unc));
    // pw a_c' x_unc with the scaled entries: no overflow for a huge row.
    const int r = c - kN;
    S ax = S(0);
    for (int k = 0; k < p.a_nnz[r]; ++k) ax += (p.a_val[r][k] * pw) * ws.x_unc[p.a_col[r][k]];
    return static_cast<S>(side) * (b * pw - ax);
  }

  // Computes sigma pw L^-1 a_c into slot; returns |m|^2.
  // Entries before m_start are never read (every use of a row starts at its
  // m_start), so only start..n-1 are written.
  S build_row(int c, int side, int slot) {
    S* row = ws.m_rows[slot];
    int start;
    if (is_bound(c)) {
      start = c;
      for (int j = start; j < p.n; ++j) row[j] = S(0);
      row[c] = S(1);
    } else {
      const int r = c - kN;
      start = p.a_nnz[r] > 0 ? p.a_col[r][0] : p.n;
      for (int j = start; j < p.n; ++j) row[j] = S(0);
      const S pw = row_power(c);
      if (pw == S(1)) {
        for (int k = 0; k < p.a_nnz[r]; ++k) row[p.a_col[r][k]] = p.a_val[r][k];
      } else {
        for (int k = 0; k < p.a_nnz[r]; ++k) row[p.a_col[r][k]] = p.a_val[r][k] * pw;
      }
    }
    int parity = -1;
    if (ws.even_band) {
      band::forward_solve<2>(ws.chol, p.n, row, start);
      parity = row_parity(c);
    } else {
      band::forward_solve(ws.chol, p.n, row, start);
    }
    S norm2 = S(0);
    const S sg = static_cast<S>(side);
    if (parity >= 0) {
      // The other parity's entries are exact zeros: their squares add
      // nothing (norm2 is never -0), and their sign is never observed.
      for (int j = start + ((start ^ parity) & 1); j < p.n; j += 2) {
        row[j] *= sg;
        norm2 += row[j] * row[j];
      }
    } else {
      for (int j = start; j < p.n; ++j) {
        row[j] *= sg;
        norm2 += row[j] * row[j];
      }
    }
    ws.m_start[slot] = static_cast<std::int16_t>(start);
    ws.m_parity[slot] = static_cast<std::int8_t>(parity);
    return norm2;
  }

  // With even_band: the index parity shared by all nonzero columns of
  // constraint c (a bound: its variable's), or -1 if they mix both.
  int row_parity(int c) const {
    if (is_bound(c)) return c & 1;
    const int r = c - kN;
    const int nnz = p.a_nnz[r];
    if (nnz == 0) return -1;
    const int parity = p.a_col[r][0] & 1;
    for (int k = 1; k < nnz; ++k) {
      if ((p.a_col[r][k] & 1) != parity) return -1;
    }
    return parity;
  }

  // dense_dot(a, b, from) for two rows whose nonzeros lie only at indices of
  // parity `parity`: the same terms into the same partial sums in the same
  // order, without the zero products in between (a sum that starts at +0 is
  // never -0, so adding a zero product leaves it unchanged).
  // dense_dot puts term j of its main part (a multiple of 4 terms from
  // `from`) into partial sum (j - from) mod 4 and the rest into s0, and
  // returns (s0 + s1) + (s2 + s3). Here the terms of one parity alternate
  // between two of the partial sums; the other two stay +0, and x + (+0) = x.
  S parity_dot(const S* a, const S* b, int from, int parity) const {
    const int main_end = from + ((p.n - from) & ~3);
    S lo = S(0), hi = S(0);  // partial sums 0 and 2, or 1 and 3
    int j = from + ((from ^ parity) & 1);
    for (; j < main_end; j += 4) {
      lo += a[j] * b[j];
      hi += a[j + 2] * b[j + 2];
    }
    if (((from ^ parity) & 1) == 0) {
      // s0 = lo and then the tail, s2 = hi, s1 = s3 = +0.
      for (; j < p.n; j += 2) lo += a[j] * b[j];
      return lo + hi;
    }
    // s1 = lo, s3 = hi, s2 = +0, s0 = the tail alone.
    S s0 = S(0);
    for (; j < p.n; j += 2) s0 += a[j] * b[j];
    return (s0 + lo) + hi;
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
    if (ws.even_band) {
      const int pa = ws.m_parity[slot_a], pb = ws.m_parity[slot_b];
      if (pa >= 0 && pb >= 0) {
        // Rows of opposite parity: every product is a zero, the sum +0.
        if (pa != pb) return S(0);
        return parity_dot(ws.m_rows[slot_a], ws.m_rows[slot_b], a > b ? a : b, pa);
      }
    }
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
    ws.fwd_valid = 0;
    ws.last_singular = false;
    ws.free_count = kA;
    for (int i = 0; i < kA; ++i) ws.free_slots[i] = static_cast<std::int16_t>(kA - 1 - i);
    std::fill_n(ws.active_side, kC, std::int8_t(0));  // a memset
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
      ws.d_w[i] = ws.d_w[i + 1];
    }
    ws.w_size = w - 1;
    // Rows r.. of the factor changed: their forward entries must be redone.
    if (ws.fwd_valid > r) ws.fwd_valid = r;
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
    ws.fwd_valid = 0;
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

  // x = xn, adding the step's length per block of variables to path_len (for
  // the scan's row-skipping bound), rounded up so that it bounds the exact length.
  void move_to(const S* xn) {
    const S inflate = S(1) + S(64) * std::numeric_limits<S>::epsilon();
    const int nb = (p.n + kScanBlock - 1) >> kScanBlockShift;
    S* __restrict x = ws.x;
    for (int b = 0; b < nb; ++b) {
      const int j0 = b << kScanBlockShift;
      const int j1 = j0 + kScanBlock < p.n ? j0 + kScanBlock : p.n;
      S s2 = S(0);
      for (int j = j0; j < j1; ++j) {
        const S dx = xn[j] - x[j];
        s2 += dx * dx;
        x[j] = xn[j];
      }
      ws.path_len[b] += std::sqrt(s2) * inflate;
    }
  }

  // u[from..n-1] -= l * row[from..n-1]; a row of one parity (m_parity) only
  // at its nonzeros: u is never -0, so u - l * (+-0) = u for the others.
  void subtract_row(S* __restrict u, const S* __restrict row, S l, int from, int parity) const {
    if (parity >= 0) {
      for (int j = from + ((from ^ parity) & 1); j < p.n; j += 2) u[j] -= l * row[j];
      return;
    }
    for (int j = from; j < p.n; ++j) u[j] -= l * row[j];
  }

  // u = -M_W' lambda (the rows with lambda_i != 0, in W order), then
  // x = L^-T u + x_unc.
  void primal_from_dual() {
    S* u = ws.u;
    for (int j = 0; j < p.n; ++j) u[j] = S(0);
    for (int i = 0; i < ws.w_size; ++i) {
      const S li = ws.lambda[i];
      if (li == S(0)) continue;
      const int slot = ws.slot_of[i];
      subtract_row(u, ws.m_rows[slot], li, ws.m_start[slot], ws.m_parity[slot]);
    }
    S* __restrict xn = ws.scratch2;  // N + 1 >= n entries
    for (int j = 0; j < p.n; ++j) xn[j] = u[j];
    if (ws.even_band) {
      band::backward_solve<2>(ws.chol, p.n, xn);
    } else {
      band::backward_solve(ws.chol, p.n, xn);
    }
    const S* __restrict xu = ws.x_unc;
    for (int j = 0; j < p.n; ++j) xn[j] += xu[j];
    move_to(xn);
  }

  // Iterative refinement of x on the final working set, from the problem
  // data. x = L^-T u + x_unc loses digits when |x_unc| >> |x| (a singular H
  // with its proximal term gives |x_unc| ~ |g| / eps), so the active
  // constraints hold only to eps_mach |a| |x_unc|. With the residuals
  //     rho_i = sigma_i pw_i (b_i - a_i'x)     (computed in x-space)
  // the correction du = -M_W' dlambda with K dlambda = -rho makes
  // m_i'(u + du) meet them (m_i'du = rho_i), and dx = L^-T du keeps
  // stationarity (dx is in the range of H^-1 A_W'). dx is small, so no
  // cancellation: the residuals drop to eps_mach |a| |x|.
  // Scratch: scratch (rho, dlambda), scratch2 (du, then x + dx).
  void polish() {
    const int w = ws.w_size;
    S* rho = ws.scratch;
    for (int i = 0; i < w; ++i) {
      const int c = ws.w_index[i];
      const S b = ws.w_side[i] > 0 ? upper(c) : lower(c);
      const S pw = row_power(c);
      rho[i] = -static_cast<S>(ws.w_side[i]) * pw * (b - dot_a(c, ws.x));
    }
    ldl::solve(ws.ldl_l, ws.ldl_d, w, rho);  // dlambda
    S* du = ws.scratch2;
    for (int j = 0; j < p.n; ++j) du[j] = S(0);
    for (int i = 0; i < w; ++i) {
      ws.lambda[i] += rho[i];
      const int slot = ws.slot_of[i];
      const S* row = ws.m_rows[slot];
      for (int j = ws.m_start[slot]; j < p.n; ++j) du[j] -= rho[i] * row[j];
    }
    for (int j = 0; j < p.n; ++j) ws.u[j] += du[j];
    band::backward_solve(ws.chol, p.n, du);
    for (int j = 0; j < p.n; ++j) du[j] += ws.x[j];
    move_to(du);
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

  // The final check of a candidate optimum, in x-space and from the problem
  // data: x finite, and every active constraint within its bounds up to
  // primal_tolerance + refactor_tolerance (1 + |b|), on the row scaled to unit
  // norm (b its bound; the same relative accuracy that the working set's
  // residual check accepts), and within the unscaled contract (within_unscaled
  // below). Inactive constraints were just checked by the scan (both tests),
  // which cannot miss a violation while x is finite.
  // Scaled violation of constraint c minus its final tolerance (<= 0: fine).
  S excess_violation(int c) const {
    const S ax = dot_a(c, ws.x);
    const S up = ax - upper(c);
    const S lo = lower(c) - ax;
    const S v = (up > lo ? up : lo) * ws.row_scale[c];
    const S b = std::abs(up > lo ? upper(c) : lower(c)) * ws.row_scale[c];
    return v - (s.primal_tolerance + s.refactor_tolerance * (S(1) + b));
  }

  // The unscaled contract (docs/qp.md, "Feasibility contract"): the violation
  // v of constraint c at x, in the problem's own units, is at most
  // unscaled_tolerance() max(1, sum_k |a_k x_k|, |b|). A row of norm |a| >> 1
  // passes the unit-row test above with v up to (primal_tolerance + ...) |a|
  // whatever x and b are; this test ties v to the magnitudes that a'x and b
  // actually have.
  S unscaled_tolerance() const { return s.primal_tolerance + s.refactor_tolerance; }

  // v <= unscaled_tolerance() max(1, mag, |b|) for a'x = ax, mag = sum |a_k x_k|,
  // all in the same units (pw: the exact power of two they are scaled by).
  bool within_unscaled(S ax, S mag, S lo, S hi, S pw) const {
    const S up = ax - hi;
    const S dn = lo - ax;
    const S b = std::abs(up > dn ? hi : lo);
    if (b > mag) mag = b;
    if (mag < pw) mag = pw;
    return (up > dn ? up : dn) <= unscaled_tolerance() * mag;
  }

  // Both tests of constraint c at x: excess_violation(c) <= 0 (the same
  // arithmetic, inlined) and the unscaled contract, whose sum sum |a_k x_k| is
  // needed only when v exceeds the tolerance (max(1, ...) >= 1). A row scaled
  // by pw != 1 is tested on the row times pw (the same inequality; no
  // overflow for a huge row).
  bool constraint_verified(int c) const {
    if (is_bound(c)) {
      const S ax = ws.x[c];
      const S up = ax - p.ub[c];
      const S lo = p.lb[c] - ax;
      const S v = up > lo ? up : lo;  // row_scale of a bound is 1
      const S b = std::abs(up > lo ? p.ub[c] : p.lb[c]);
      if (!(v - (s.primal_tolerance + s.refactor_tolerance * (S(1) + b)) <= S(0))) return false;
      // max(1, ...) >= 1: a violation up to the tolerance passes at once.
      return v <= unscaled_tolerance() || within_unscaled(ax, std::abs(ax), p.lb[c], p.ub[c], S(1));
    }
    const int r = c - kN;
    const S pw = row_power(c);
    if (pw != S(1)) {
      if (!(excess_violation(c) <= S(0))) return false;
      S ax = S(0), mag = S(0);
      for (int k = 0; k < p.a_nnz[r]; ++k) {
        const S prod = (p.a_val[r][k] * pw) * ws.x[p.a_col[r][k]];
        ax += prod;
        mag += std::abs(prod);
      }
      return within_unscaled(ax, mag, p.lba[r] * pw, p.uba[r] * pw, pw);
    }
    const S ax = p.row_dot(r, ws.x);
    const S up = ax - p.uba[r];
    const S lo = p.lba[r] - ax;
    const S v = (up > lo ? up : lo) * ws.row_scale[c];
    const S b = std::abs(up > lo ? p.uba[r] : p.lba[r]) * ws.row_scale[c];
    if (!(v - (s.primal_tolerance + s.refactor_tolerance * (S(1) + b)) <= S(0))) return false;
    if ((up > lo ? up : lo) <= unscaled_tolerance()) return true;  // as for a bound
    S mag = S(0);
    for (int k = 0; k < p.a_nnz[r]; ++k) mag += std::abs(p.a_val[r][k] * ws.x[p.a_col[r][k]]);
    return within_unscaled(ax, mag, p.lba[r], p.uba[r], S(1));
  }

  bool primal_verified() const {
    for (int j = 0; j < p.n; ++j) {
      if (!std::isfinite(ws.x[j])) return false;
    }
    for (int i = 0; i < ws.w_size; ++i) {
      if (!constraint_verified(ws.w_index[i])) return false;
    }
    if (ws.set_aside > 0) {
      for (int c = 0; c < kC; ++c) {
        if (ws.active_side[c] == kSetAside && !constraint_verified(c)) return false;
      }
    }
    return true;
  }

  // Clears the set-aside marks (end of a solve; hot starts reuse active_side).
  void clear_set_aside() {
    if (ws.set_aside == 0) return;
    for (int c = 0; c < kC; ++c) {
      if (ws.active_side[c] == kSetAside) ws.active_side[c] = 0;
    }
    ws.set_aside = 0;
  }

  // Multiplier (or ray component) y of constraint c in the transformed
  // problem, stored in the problem's own units: a row scaled by pw has the
  // multiplier pw y (row_scaling.hpp).
  void store_multiplier(int c, S y, QpResult<D>& res) const {
    const S pw = row_power(c);
    if (pw != S(1)) y *= pw;
    if (is_bound(c)) {
      res.y_bounds[c] = y;
    } else {
      res.y_rows[c - kN] = y;
    }
  }

  // The dual ray of a dependent last row (direction `dir`, M_W' dir = 0) in
  // the problem's own units, written to res.y_*, and its independent check.
  bool certify_infeasible(const S* dir, QpResult<D>& res) const {
    for (int j = 0; j < p.n; ++j) res.y_bounds[j] = S(0);
    for (int r = 0; r < p.m; ++r) res.y_rows[r] = S(0);
    const int w = ws.w_size;
    for (int i = 0; i < w; ++i) {
      const int c = ws.w_index[i];
      S y = static_cast<S>(ws.w_side[i]) * dir[i];
      // An inequality's component is >= -ptol by the ratio test; its rounding
      // residue below zero would point at the other (maybe infinite) side.
      if (!is_equality(c) && static_cast<S>(ws.w_side[i]) * y < S(0)) y = S(0);
      store_multiplier(c, y, res);
    }
    const RayCheck<S> check = check_dual_ray(p, res.y_bounds, res.y_rows, s.certificate_radius);
    res.certificate_residual = check.residual;
    res.certificate_gap = check.gap;
    return check.holds;
  }

  // One step of iterative refinement of lambda* (K lambda* = -d_W) with the
  // same factor: with u* = -M_W' lambda*, the residual is
  //     rho = -d - K lambda* = M_W u* - d,   and   lambda* += K^-1 rho.
  // Used only once a candidate optimum has failed its accuracy checks after
  // every refactorisation (the factor is then as good as it gets, and the
  // multipliers of an ill-conditioned K are what is left to improve), as is
  // polish() (always used with a singular H).
  // Scratch: ws.u (u*; recomputed by primal_from_dual before any use),
  // scratch2 (rho, then the correction).
  void refine_multipliers(S* lambda_star) {
    const int w = ws.w_size;
    S* us = ws.u;
    S* rho = ws.scratch2;
    for (int j = 0; j < p.n; ++j) us[j] = S(0);
    for (int i = 0; i < w; ++i) {
      const int slot = ws.slot_of[i];
      const S* row = ws.m_rows[slot];
      for (int j = ws.m_start[slot]; j < p.n; ++j) us[j] -= lambda_star[i] * row[j];
    }
    for (int i = 0; i < w; ++i) {
      const int slot = ws.slot_of[i];
      rho[i] = dense_dot(ws.m_rows[slot], us, ws.m_start[slot]) - ws.d_w[i];
    }
    ldl::solve(ws.ldl_l, ws.ldl_d, w, rho);
    for (int i = 0; i < w; ++i) lambda_star[i] += rho[i];
  }

  // lambda* = -K^-1 d_W into `out` (w entries), with the forward half cached
  // in fwd_d: the same operations in the same order as ldl::solve (bit-
  // identical results), but only the entries from fwd_valid on are redone
  // (after an add that is one row, O(w) instead of O(w^2) for the forward half).
  void multipliers(S* out) {
    const int w = ws.w_size;
    S* y = ws.fwd_d;
    for (int i = ws.fwd_valid; i < w; ++i) {
      const S* li = ws.ldl_l + ldl::row_offset(i);
      S acc = -ws.d_w[i];
      for (int j = 0; j < i; ++j) acc -= li[j] * y[j];
      y[i] = acc;
    }
    ws.fwd_valid = w;
    for (int i = 0; i < w; ++i) out[i] = y[i] / ws.ldl_d[i];
    for (int i = w - 1; i >= 0; --i) {
      const S bi = out[i];
      const S* li = ws.ldl_l + ldl::row_offset(i);
      for (int j = 0; j < i; ++j) out[j] -= li[j] * bi;
    }
  }

  // Each pass of the loop either stops, refactorises (at most
  // kMaxRefactorisations times), switches to refined multipliers (once), sets
  // a constraint aside (at most once per constraint per solve) or changes the
  // working set (counted; at most max_iterations times): at most kMaxPasses.
  static constexpr int kMaxPasses = D::kMaxIterations + D::kMaxRefactorisations + D::kMaxConstraints + 2;

  QpStatus iterate(int max_iterations, QpResult<D>& res) {
    // zero_steps: consecutive zero-length removals since the last add (the
    // switch to Bland's rule). stalled: passes since the dual iterate last
    // moved (adds do not count as progress), the cycle guard: the dual
    // objective rises strictly with every nonzero step, so a long run without
    // one is a cycle made by rounding.
    int zero_steps = 0;
    int stalled = 0;
    int last_added = -1;   // constraint added in the previous pass, else -1
    bool precise = false;  // refine lambda* (after the refactorisations failed)
    int& it = res.iterations;
    // The blocking multiplier reached 0 after a step of length `step`: its
    // constraint leaves W; a zero-length step counts towards Bland's rule.
    auto drop = [&](int block, S step) {
      ws.lambda[block] = S(0);
      remove(block);
      ++it;
      last_added = -1;
      zero_steps = step > S(0) ? 0 : zero_steps + 1;
      stalled = step > S(0) ? 0 : stalled + 1;
    };
    // WCET: the constant kMaxPasses; the passes that cost a working-set change
    // are <= max_iterations, the run-time cap (QpSettings::max_iterations, per
    // stage in itp/config.hpp: kCoarseQpMaxIterations, kPathQpMaxIterations,
    // kSpeedQpMaxIterations, lowered to what is left of a per-cycle budget).
    for (int pass = 0; pass < kMaxPasses; ++pass) {
      if (stalled > D::kMaxZeroRun) {
        // Start again from a fresh factor, once per budget.
        if (res.refactorisations >= D::kMaxRefactorisations) return QpStatus::kNumericalTrouble;
        ++res.refactorisations;
        refactor();
        stalled = 0;
        zero_steps = 0;
        continue;
      }
      const bool bland = zero_steps > D::kMaxZeroSteps;
      const int w = ws.w_size;
      if (!ws.last_singular) {
        // lambda* = -K^-1 d_W: multipliers of the equality QP on W. It lives
        // in scratch until the step below has used it (add and remove reuse
        // scratch afterwards).
        S* lambda_star = ws.scratch;
        multipliers(lambda_star);
        if (precise) refine_multipliers(lambda_star);
        int block = -1;
        S best = S(0);
        for (int i = 0; i < w; ++i) {
          if (is_equality(ws.w_index[i]) || !(lambda_star[i] < -s.dual_tolerance)) {
            continue;
          }
          const S ratio = ws.lambda[i] / (ws.lambda[i] - lambda_star[i]);
          if (block < 0 || ratio < best ||
              (ratio == best && ws.w_index[i] < ws.w_index[block])) {
            block = i;
            best = ratio;
          }
        }
        if (block < 0) {
          bool moved = false;
          for (int i = 0; i < w; ++i) {
            const S l = lambda_star[i];
            const S next = (l < S(0) && !is_equality(ws.w_index[i])) ? S(0) : l;
            moved = moved || next != ws.lambda[i];
            ws.lambda[i] = next;
          }
          stalled = moved ? 0 : stalled + 1;
          primal_from_dual();
          int side = 0;
          int c = scan::most_violated(p, ws, s.primal_tolerance, bland, &side);
          if (c < 0 && (precise || ws.proximal_weight > S(0))) {
            polish();
            c = scan::most_violated(p, ws, s.primal_tolerance, bland, &side);
          }
          if (c < 0) {
            // No row is violated on the unit row; one may still be in its own
            // units beyond the contract (a row of large norm, x and b small):
            // it is violated all the same, so it enters W like any other.
            const scan::UnscaledViolation<S> unscaled = scan::unscaled_violated(p, ws, s.primal_tolerance, unscaled_tolerance());
            if (unscaled.constraint >= 0) {
              c = unscaled.constraint;
              side = unscaled.side;
            }
          }
          if (c < 0) {
            const S resid = active_residual();
            const bool accurate = resid <= s.refactor_tolerance;
            if (!accurate || !primal_verified()) {
              if (res.refactorisations < D::kMaxRefactorisations) {
                ++res.refactorisations;
                refactor();
                continue;
              }
              if (!precise) {
                // Last resort: refined multipliers and a polished x, and the
                // set-aside constraints get their chance again with them.
                precise = true;
                clear_set_aside();
                continue;
              }
            }
            return primal_verified() ? QpStatus::kOptimal : QpStatus::kNumericalTrouble;
          }
          if (it >= max_iterations) return QpStatus::kIterationLimit;
          // |W| = n + 1 with an independent last row cannot happen in exact
          // arithmetic: the factor has lost rank information.
          if (ws.w_size >= kA) return QpStatus::kNumericalTrouble;
          add(c, side);
          last_added = c;
          ++it;
          zero_steps = 0;
        } else {
          if (it >= max_iterations) return QpStatus::kIterationLimit;
          const int leaving = ws.w_index[block];
          if (leaving == last_added && !(best > S(0))) {
            // The constraint just added leaves again at once, x unchanged: in
            // exact arithmetic a violated constraint enters with a positive
            // multiplier, so its violation is rounding of W. Removing it
            // would select it again (a cycle); set it aside instead.
            remove(block);
            ws.active_side[leaving] = kSetAside;
            ++ws.set_aside;
            last_added = -1;
            ++stalled;
            continue;
          }
          for (int i = 0; i < w; ++i) {
            ws.lambda[i] += best * (lambda_star[i] - ws.lambda[i]);
          }
          drop(block, best);
        }
      } else {
        // Dependent last row: p with M_W' p = 0, p_last = 1, is a direction of
        // dual ascent (it raises the violated constraint's multiplier without
        // moving u). Step until an inequality multiplier reaches zero.
        S* dir = ws.scratch;
        ldl::null_vector(ws.ldl_l, w, dir);
        // Along dir the dual objective -1/2|M'lambda|^2 - lambda'd rises at
        // the rate -dir'd_W (M'dir = 0). A rate at the rounding level of its
        // terms means the violated row is a combination of W that W already
        // meets, violated only by the rounding of the rows it combines:
        // stepping along dir makes no progress and can cycle (add it, drop
        // another, add that, drop it again). Set the row aside instead.
        S ascent = S(0), terms = S(0);
        for (int i = 0; i < w; ++i) {
          ascent -= dir[i] * ws.d_w[i];
          terms += std::abs(dir[i] * ws.d_w[i]);
        }
        if (!(ascent > S(16) * static_cast<S>(w) * std::numeric_limits<S>::epsilon() * terms)) {
          const int c = ws.w_index[w - 1];
          remove(w - 1);
          ws.active_side[c] = kSetAside;
          ++ws.set_aside;
          continue;
        }
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
        if (block < 0) {
          // Unbounded dual ray: infeasible if the ray passes its check. If
          // not, the factor built by updates may have degraded: recompute it
          // from scratch and look again (bounded); a ray that still fails
          // comes from a working set that is only nearly dependent.
          if (certify_infeasible(dir, res)) return QpStatus::kInfeasible;
          if (res.refactorisations >= D::kMaxRefactorisations) return QpStatus::kNumericalTrouble;
          ++res.refactorisations;
          refactor();
          continue;
        }
        if (it >= max_iterations) return QpStatus::kIterationLimit;
        for (int i = 0; i < w; ++i) ws.lambda[i] += best * dir[i];
        drop(block, best);
      }
    }
    return QpStatus::kIterationLimit;
  }

  // Multipliers (or, for kInfeasible, the ray already in res), working set
  // and the objective 1/2 x'Hx + g'x of the ORIGINAL H (never H + eps I).
  void write_result(QpStatus status, QpResult<D>& res) {
    res.status = status;
    for (int j = 0; j < p.n; ++j) res.x[j] = ws.x[j];
    const bool ray = status == QpStatus::kInfeasible;
    if (!ray) {
      for (int j = 0; j < p.n; ++j) res.y_bounds[j] = S(0);
      for (int r = 0; r < p.m; ++r) res.y_rows[r] = S(0);
    }
    res.working_set.clear();
    const int w = ws.w_size - (ws.last_singular ? 1 : 0);
    for (int i = 0; i < w; ++i) {
      const int c = ws.w_index[i];
      if (!ray) store_multiplier(c, static_cast<S>(ws.w_side[i]) * ws.lambda[i], res);
      (void)res.working_set.push(is_bound(c) ? c : c - kN, is_bound(c), ws.w_side[i]);
    }
    res.objective = objective_value(p, ws.x, ws.scratch2);
  }
};

}  // namespace itp::qp::detail
