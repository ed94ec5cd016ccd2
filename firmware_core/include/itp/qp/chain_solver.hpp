#pragma once
// Primal active-set solver for one chain (chain_form.hpp), docs/qp.md
// "Chain solver". Why a second solver: on a chain every working set W is a
// partition of the positions into segments (runs joined by active links),
// each either free or fixed by one active bound. Eliminating W leaves one
// unknown y_s per free segment,
//   x_q = y_s + o_q   (o_q: the sum of the active link values from the segment's start),
// and a reduced Hessian Z'HZ that is again pentadiagonal (a segment couples
// only with segments at most two positions away). So every equality-
// constrained subproblem costs O(n) from scratch, and W may change by many
// constraints at once: the start clamps the unconstrained optimum onto the
// feasible set and takes every constraint it clamps against as active (one
// primal-dual active-set step), and the primal iterations then repair that
// guess: add the blocking constraint, or drop the constraints whose
// multipliers have the wrong sign (solve() says when one at a time).
//
// Multipliers along a segment a..b with its bound (if any) at k*
// (stationarity r + y_bounds + sum_links y_q (e_{q+1} - e_q) = 0, r = Hx + g):
//   y_bound(k*) = -sum_{a..b} r,   y_link(q) = sum_{a..q} r + [q >= k*] y_bound(k*).
// Sign convention of QpResult: y < 0 lower side active, y > 0 upper side.
#include <cmath>
#include <cstdint>
#include <limits>

#include "itp/qp/chain_form.hpp"
#include "itp/qp/pentadiagonal_ldl.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp::chain {

// Marks of the working set: per position its bound, per link its side.
inline constexpr std::int8_t kInactive = 0;
inline constexpr std::int8_t kLower = -1;
inline constexpr std::int8_t kUpper = 1;
inline constexpr std::int8_t kFixed = 2;  // lb == ub: always active, either sign

template <class D, int L>
class ChainSolver {
  using S = typename D::Scalar;
 public:
  static constexpr std::size_t kLz = static_cast<std::size_t>(L);

  ChainSolver(const ChainData<D, L>& chain, const QpSettings<S>& settings) : ch_(chain), s_(settings) {}

  // A cold solve: up to `cap` working-set changes, added to `iterations`. True
  // with x() optimal (KKT within the tolerances, x feasible); false when the
  // chain is infeasible, its reduced H not positive definite, or the cap or
  // a check is hit: the general solver must settle the problem.
  bool solve(int cap, int& iterations);

  const S* x() const { return x_; }
  int factorisations() const { return factorisations_; }  // equality solves, each from scratch
  // After solve() returned true (they share storage with the equality solve).
  S bound_multiplier(int q) const { return offset_[q]; }
  S link_multiplier(int q) const { return rhs_[q]; }
  std::int8_t bound_mark(int q) const { return bound_[q]; }
  std::int8_t link_mark(int q) const { return link_[q]; }

 private:
  // W = the fixed variables only (lb == ub).
  void clear_marks() {
    for (int q = 0; q < length(); ++q) {  // < L
      bound_[q] = ch_.lb[q] == ch_.ub[q] ? kFixed : kInactive;
      link_[q] = kInactive;
    }
  }
  void independent_marks();
  bool equality_solve();
  int feasible_start();
  S multipliers(S& hx_scale);
  int ratio_test(S& alpha, int& kind, std::int8_t& side) const;
  bool final_check() const;
  // The chain's length, visibly at most L (for the compiler's bounds checks
  // as much as for the reader: gather() never makes it longer).
  int length() const { return ch_.n < L ? ch_.n : L; }
  S bound_value(int q, std::int8_t side) const { return side == kUpper ? ch_.ub[q] : ch_.lb[q]; }
  S link_value(int q, std::int8_t side) const { return side == kUpper ? ch_.link_hi[q] : ch_.link_lo[q]; }

  const ChainData<D, L>& ch_;
  const QpSettings<S>& s_;
  int factorisations_ = 0;
  std::int8_t bound_[kLz];       // per position
  std::int8_t link_[kLz];        // per link q -> q + 1
  std::int16_t segment_[kLz];    // segment of position q
  std::int16_t free_[kLz];       // free index of segment s, -1: fixed
  std::int16_t position_free_[kLz + 2];  // [q + 2]: free index of position q's segment, -1: fixed
  S x0_[kLz + 4];                // [q + 2]: x with every free y = 0; 0 outside the chain
  S base_[kLz];                  // value of segment s at offset 0 (0 while free)
  // o_q during an equality solve; after it (multipliers()) the bound multipliers
  S offset_[kLz];
  S x_[kLz];                     // feasible iterate
  S xe_[kLz];                    // equality-constrained optimum for W
  S r_[kLz];                     // H x + g
  S band_[kLz][3];               // reduced Hessian, lower band (half-bandwidth 2)
  S factor_[kLz][3];
  // Z'(-Hx0 - g), then y, during an equality solve; after it the link multipliers
  S rhs_[kLz];
};

// Keeps the marks linearly independent: at most one bound per segment.
// Scanning left to right, a link that would join two bounded segments, or a
// bound in a segment that has one, is dropped (fixed positions stay).
template <class D, int L>
void ChainSolver<D, L>::independent_marks() {
  bool bounded = false;
  for (int q = 0; q < length(); ++q) {  // < L
    const bool joined = q > 0 && link_[q - 1] != kInactive;
    if (joined && bounded && bound_[q] == kFixed) link_[q - 1] = kInactive;
    if (q == 0 || link_[q - 1] == kInactive) bounded = false;
    if (bound_[q] != kInactive && bound_[q] != kFixed && bounded) bound_[q] = kInactive;
    bounded = bounded || bound_[q] != kInactive;
  }
}

// xe = argmin of the QP with every marked constraint as an equality.
template <class D, int L>
bool ChainSolver<D, L>::equality_solve() {
  ++factorisations_;
  const int n = length();
  int segments = 0;
  S offset = S(0);
  for (int q = 0; q < n; ++q) {  // < L: segments, offsets, fixed values
    if (q == 0 || link_[q - 1] == kInactive) {
      offset = S(0);
      free_[segments] = 0;
      base_[segments] = S(0);
      ++segments;
    } else {
      offset += link_value(q - 1, link_[q - 1]);
    }
    offset_[q] = offset;
    segment_[q] = static_cast<std::int16_t>(segments - 1);
    if (bound_[q] != kInactive) {
      free_[segments - 1] = -1;
      base_[segments - 1] = bound_value(q, bound_[q]) - offset;
    }
  }
  int free_count = 0;
  for (int k = 0; k < segments; ++k) {  // < L
    if (free_[k] == 0) free_[k] = static_cast<std::int16_t>(free_count++);
  }
  position_free_[0] = position_free_[1] = -1;
  x0_[0] = x0_[1] = S(0);
  for (int q = 0; q < n; ++q) {  // < L: x0 (every free y = 0), each position's free index
    const int k = segment_[q];
    position_free_[q + 2] = free_[k];
    x0_[q + 2] = offset_[q] + base_[k];
  }
  x0_[n + 2] = x0_[n + 3] = S(0);
  // Row f of Z'HZ and of -Z'(H x0 + g), pulled position by position: each
  // pair (q', q), q' < q, enters at the later position q, in row f(q).
  const auto& h0 = ch_.h0;
  const auto& h1 = ch_.h1;
  const auto& h2 = ch_.h2;
  const auto& g = ch_.g;
  const S* x0 = x0_ + 2;          // x0[-2], x0[-1], x0[n], x0[n+1] are 0
  const std::int16_t* pf = position_free_ + 2;  // pf[-2], pf[-1] are -1
  for (int q = 0; q < n; ++q) {  // < L
    const int f = pf[q];
    if (f < 0) continue;
    const S h1_before = q >= 1 ? h1[q - 1] : S(0);
    const S h2_before = q >= 2 ? h2[q - 2] : S(0);
    const S h1_after = q + 1 < n ? h1[q] : S(0);
    const S h2_after = q + 2 < n ? h2[q] : S(0);
    const S hx = h2_before * x0[q - 2] + h1_before * x0[q - 1] + h0[q] * x0[q] + h1_after * x0[q + 1] +
                 h2_after * x0[q + 2];
    const int f1 = pf[q - 1];
    const int f2 = pf[q - 2];
    if (f1 != f && f2 != f) {  // q starts its segment: a new row
      band_[f][0] = band_[f][1] = band_[f][2] = S(0);
      rhs_[f] = S(0);
    }
    rhs_[f] -= hx + g[q];
    band_[f][0] += h0[q];
    if (f1 >= 0) band_[f][f - f1] += f1 == f ? S(2) * h1_before : h1_before;
    if (f2 >= 0) band_[f][f - f2] += f2 == f ? S(2) * h2_before : h2_before;
  }
  if (free_count > 0) {
    if (!penta::factor(band_, factor_, free_count)) return false;
    penta::solve(factor_, free_count, rhs_);
  }
  for (int q = 0; q < n; ++q) {  // < L
    const int f = pf[q];
    xe_[q] = x0[q] + (f >= 0 ? rhs_[f] : S(0));
  }
  return true;
}

// From the target xe (the equality optimum with the fixed variables only):
// x = the feasible point that follows xe, clamped left to right into what the
// bounds, the link to x_{q-1} and every later constraint (reach, a backward
// pass) still allow; exact for a chain. Marks: every constraint x was clamped
// against. Returns how many positions were clamped (0: x = xe, still the
// optimum for the marks), or -1: infeasible.
template <class D, int L>
int ChainSolver<D, L>::feasible_start() {
  S* reach_lo = r_;    // scratch: r_ and rhs_ are rewritten by the next solve
  S* reach_hi = rhs_;
  reach_lo[length() - 1] = ch_.lb[length() - 1];
  reach_hi[length() - 1] = ch_.ub[length() - 1];
  for (int q = length() - 2; q >= 0; --q) {  // < L
    const S lo = reach_lo[q + 1] - ch_.link_hi[q];
    const S hi = reach_hi[q + 1] - ch_.link_lo[q];
    reach_lo[q] = lo > ch_.lb[q] ? lo : ch_.lb[q];
    reach_hi[q] = hi < ch_.ub[q] ? hi : ch_.ub[q];
    if (!(reach_lo[q] <= reach_hi[q])) return -1;
  }
  if (!(reach_lo[length() - 1] <= reach_hi[length() - 1])) return -1;
  int moved = 0;
  for (int q = 0; q < length(); ++q) {  // < L
    S lo = reach_lo[q], hi = reach_hi[q];
    std::int8_t lo_by = lo == ch_.lb[q] ? std::int8_t(1) : std::int8_t(0);  // 1 bound, 2 link
    std::int8_t hi_by = hi == ch_.ub[q] ? std::int8_t(1) : std::int8_t(0);
    if (q > 0) {
      const S a = x_[q - 1] + ch_.link_lo[q - 1];
      const S b = x_[q - 1] + ch_.link_hi[q - 1];
      if (a > lo) lo = a, lo_by = 2;
      if (b < hi) hi = b, hi_by = 2;
    }
    if (hi < lo) hi = lo;  // rounding of the reach: keep the lower end
    const S target = xe_[q];
    // Within rounding of [lo, hi] the target is not clamped against anything.
    const S slack = s_.primal_tolerance * (S(1) + std::fabs(target));
    const bool keep = target >= lo - slack && target <= hi + slack;
    x_[q] = target < lo ? lo : (target > hi ? hi : target);
    const std::int8_t by = keep ? std::int8_t(0) : (target < lo ? lo_by : hi_by);
    const std::int8_t side = target < lo ? kLower : kUpper;
    if (q > 0) link_[q - 1] = by == 2 ? side : kInactive;
    if (bound_[q] != kFixed) bound_[q] = by == 1 ? side : kInactive;
    if (bound_[q] == kLower) x_[q] = ch_.lb[q];
    if (bound_[q] == kUpper) x_[q] = ch_.ub[q];
    moved += keep ? 0 : 1;
  }
  independent_marks();
  return moved;
}

// y_bound, y_link at x (= xe) from r = Hx + g, segment by segment. Returns
// the largest |sum_s r| of a free segment (0 in exact arithmetic); hx_scale:
// max |(Hx)_q|.
template <class D, int L>
typename D::Scalar ChainSolver<D, L>::multipliers(S& hx_scale) {
  S* y_bound = offset_;  // free once xe_ is formed
  S* y_link = rhs_;
  ch_.multiply(x_, r_);
  S residual = S(0);
  hx_scale = S(0);
  for (int q = 0; q < length(); ++q) {  // < L
    const S a = std::fabs(r_[q]);
    if (a > hx_scale) hx_scale = a;
    r_[q] += ch_.g[q];
    y_bound[q] = S(0);
    y_link[q] = S(0);
  }
  int a = 0;
  for (int b = 0; b < length(); ++b) {  // < L: segment a..b ends at b
    if (b + 1 < length() && link_[b] != kInactive) continue;
    S total = S(0);
    int held = -1;
    for (int q = a; q <= b; ++q) {  // < L
      total += r_[q];
      if (bound_[q] != kInactive) held = q;
    }
    const S y_held = held >= 0 ? -total : S(0);
    if (held >= 0) y_bound[held] = y_held;
    if (held < 0 && !(std::fabs(total) <= residual)) residual = std::fabs(total);  // NaN too
    S partial = S(0);
    for (int q = a; q < b; ++q) {  // < L
      partial += r_[q];
      y_link[q] = partial + (held >= 0 && q >= held ? y_held : S(0));
    }
    a = b + 1;
  }
  return residual;
}

// Largest step along xe - x that keeps every inactive constraint; kind 1: a
// bound at position `which`, 2: a link; 0: none blocks (alpha = 1).
template <class D, int L>
int ChainSolver<D, L>::ratio_test(S& alpha, int& kind, std::int8_t& side) const {
  alpha = S(1);
  kind = 0;
  side = kInactive;
  int which = -1;
  for (int q = 0; q < length(); ++q) {  // < L
    if (bound_[q] != kInactive || free_[segment_[q]] < 0) continue;
    const S p = xe_[q] - x_[q];
    if (p < S(0) && ch_.lb[q] > -std::numeric_limits<S>::infinity()) {
      const S t = (ch_.lb[q] - x_[q]) / p;
      if (t < alpha) alpha = t, kind = 1, which = q, side = kLower;
    } else if (p > S(0) && ch_.ub[q] < std::numeric_limits<S>::infinity()) {
      const S t = (ch_.ub[q] - x_[q]) / p;
      if (t < alpha) alpha = t, kind = 1, which = q, side = kUpper;
    }
  }
  for (int q = 0; q + 1 < length(); ++q) {  // < L
    if (link_[q] != kInactive || ch_.link_row[q] < 0) continue;
    if (free_[segment_[q]] < 0 && free_[segment_[q + 1]] < 0) continue;
    const S dp = (xe_[q + 1] - xe_[q]) - (x_[q + 1] - x_[q]);
    const S d = x_[q + 1] - x_[q];
    if (dp < S(0) && ch_.link_lo[q] > -std::numeric_limits<S>::infinity()) {
      const S t = (ch_.link_lo[q] - d) / dp;
      if (t < alpha) alpha = t, kind = 2, which = q, side = kLower;
    } else if (dp > S(0) && ch_.link_hi[q] < std::numeric_limits<S>::infinity()) {
      const S t = (ch_.link_hi[q] - d) / dp;
      if (t < alpha) alpha = t, kind = 2, which = q, side = kUpper;
    }
  }
  if (alpha < S(0)) alpha = S(0);
  return which;
}

// x within the primal tolerance of every bound and link (in x units).
template <class D, int L>
bool ChainSolver<D, L>::final_check() const {
  const S tol = s_.primal_tolerance + s_.refactor_tolerance;
  bool ok = true;
  for (int q = 0; q < length(); ++q) {  // < L
    const S v = x_[q];
    ok = ok && std::isfinite(v) && v >= ch_.lb[q] - tol * (S(1) + std::fabs(ch_.lb[q])) &&
         v <= ch_.ub[q] + tol * (S(1) + std::fabs(ch_.ub[q]));
    if (q + 1 < length() && ch_.link_row[q] >= 0) {
      const S d = x_[q + 1] - x_[q];
      const S scale = S(1) + std::fabs(x_[q + 1]) + std::fabs(x_[q]);
      ok = ok && d >= ch_.link_lo[q] - tol * scale && d <= ch_.link_hi[q] + tol * scale;
    }
  }
  return ok;
}

// The loop. At an equality optimum every constraint whose multiplier has the
// wrong sign is dropped at once (the start's guess typically holds several
// that are not active), until a step is blocked at zero length: from then on
// one per visit, the textbook rule, so degenerate vertices cannot cycle
// through many-at-once exchanges.
template <class D, int L>
bool ChainSolver<D, L>::solve(int cap, int& iterations) {
  if (length() < 1) return false;
  clear_marks();
  if (!equality_solve()) return false;
  const int moved = feasible_start();
  if (moved < 0) return false;
  S g_scale = S(1);
  for (int q = 0; q < length(); ++q) {  // < L
    const S a = std::fabs(ch_.g[q]);
    if (a > g_scale) g_scale = a;
  }
  const S dual_tol = s_.dual_tolerance * g_scale;
  bool current = moved == 0;  // xe_ is still the equality optimum of the marks
  bool spread = true;         // drop every wrong sign at once
  const int start_changes = iterations;
  for (int pass = 0; pass <= cap; ++pass) {  // <= cap + 1 solves: every pass but the last changes W
    if (!current && !equality_solve()) return false;
    current = false;
    S alpha = S(1);
    int kind = 0;
    std::int8_t side = kInactive;
    const int which = ratio_test(alpha, kind, side);
    if (kind != 0) {  // blocked: step to the constraint and add it
      if (iterations - start_changes >= cap) return false;
      for (int q = 0; q < length(); ++q) x_[q] += alpha * (xe_[q] - x_[q]);  // < L
      if (kind == 1) {
        bound_[which] = side;
        x_[which] = bound_value(which, side);
      } else {
        link_[which] = side;
      }
      spread = spread && alpha > S(0);
      ++iterations;
      continue;
    }
    for (int q = 0; q < length(); ++q) x_[q] = xe_[q];  // < L
    S hx_scale = S(0);
    const S residual = multipliers(hx_scale);
    S worst = dual_tol;  // the wrong sign by the most (one-per-visit rule)
    int drop = -1;
    bool drop_link = false;
    int dropped = 0;
    for (int q = 0; q < length(); ++q) {  // < L
      const S yb = bound_[q] == kLower ? offset_[q] : (bound_[q] == kUpper ? -offset_[q] : S(0));
      const S yl = link_[q] == kLower ? rhs_[q] : (link_[q] == kUpper ? -rhs_[q] : S(0));
      if (yb > worst) worst = yb, drop = q, drop_link = false;
      if (yl > worst) worst = yl, drop = q, drop_link = true;
      const bool room = spread && iterations - start_changes + dropped < cap;
      if (room && yb > dual_tol) bound_[q] = kInactive, ++dropped;
      const bool room_link = spread && iterations - start_changes + dropped < cap;
      if (room_link && yl > dual_tol) link_[q] = kInactive, ++dropped;
    }
    if (drop < 0) {
      // Free segments: their equality solve made sum_s r = 0; a residual
      // beyond rounding means the reduced solve was inaccurate.
      if (!(residual <= s_.stationarity_tolerance * (g_scale + hx_scale))) return false;
      return final_check();
    }
    if (iterations - start_changes >= cap) return false;
    if (!spread) {
      if (drop_link) {
        link_[drop] = kInactive;
      } else {
        bound_[drop] = kInactive;
      }
      dropped = 1;
    }
    iterations += dropped;
  }
  return false;
}

}  // namespace itp::qp::chain
