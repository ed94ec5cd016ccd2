#pragma once
// Active-set solver for one chain (chain_form.hpp), docs/qp.md "Chain
// solver". Why a second solver: on a chain every working set W is a
// partition of the positions into segments (runs joined by active links),
// each either free or fixed by one active bound. Eliminating W leaves one
// unknown y_s per free segment,
//   x_q = y_s + o_q   (o_q: the sum of the active link values from the segment's start),
// and a reduced Hessian Z'HZ that is again pentadiagonal (a segment couples
// only with segments at most two positions away). So every equality-
// constrained subproblem costs O(n) from scratch, and W may change by many
// constraints at once: the start clamps the unconstrained optimum onto the
// feasible set and takes every constraint it clamps against as active;
// primal-dual exchange rounds (or, warm, a guessed W) then change W many
// constraints per solve, and the primal loop, which terminates, repairs what
// they leave: add the blocking constraint, or drop the constraints whose
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
  // Exchange rounds (exchange_rounds) tried before the primal loop on a
  // chain with link rows, from the clamped start or a warm start's guess. Not
  // on a chain without (a box): there the exchange often cycles (measured:
  // docs/qp.md, "Chain solver").
  static constexpr int kExchangeRounds = 4;
  // A warm start's guess on a box chain with at most this many bounds only
  // filters the cold start (solve()).
  static constexpr int kFilterOnlyBounds = 3;

  ChainSolver(const ChainData<D, L>& chain, const QpSettings<S>& settings) : ch_(chain), s_(settings) { prepare(); }
  // Not copied: x_ points into the object's own storage.
  ChainSolver(const ChainSolver&) = delete;
  ChainSolver& operator=(const ChainSolver&) = delete;

  // A warm start's guess, before solve(): one constraint of the last working
  // set. Ignored where the chain has no such bound or link (an infinite
  // value, no link row), at fixed positions and for implied bounds.
  void guess_bound(int q, std::int8_t side) {
    if (q < 0 || q >= length() || bound_[q] == kFixed || implied(q, side)) return;
    if (std::fabs(bound_value(q, side)) < std::numeric_limits<S>::infinity()) bound_[q] = side;
  }
  void guess_link(int q, std::int8_t side) {
    if (q < 0 || q + 1 >= length() || ch_.link_row[q] < 0) return;
    if (std::fabs(link_value(q, side)) < std::numeric_limits<S>::infinity()) link_[q] = side;
  }

  // A solve: cold, or (from_guess) first from the guessed marks. Up to `cap`
  // working-set changes in all, added to `iterations`. True with
  // x() optimal (KKT within the tolerances, x feasible); false when the chain
  // is infeasible, its reduced H not positive definite, or the cap or a
  // check is hit: the general solver must settle the problem.
  bool solve(int cap, int& iterations, bool from_guess = false);

  const S* x() const { return x_; }
  int factorisations() const { return factorisations_; }  // equality solves, each from scratch
  // After solve() returned true (they share storage with the equality solve).
  S bound_multiplier(int q) const { return offset_[q]; }
  S link_multiplier(int q) const { return rhs_[q]; }
  std::int8_t bound_mark(int q) const { return bound_[q]; }
  std::int8_t link_mark(int q) const { return link_[q]; }
  // The chain's part of the objective, 1/2 x'Hx + g'x = 1/2 x'(r + g) with
  // r = Hx + g from the last multipliers() (H couples no two chains).
  S objective() const {
    S sum = S(0);
    for (int q = 0; q < length(); ++q) sum += x_[q] * (r_[q] + g_[q]);  // < L
    return S(0.5) * sum;
  }

 private:
  // W = the fixed variables only (lb == ub).
  void clear_marks() {
    for (int q = 0; q < length(); ++q) {  // < L
      bound_[q] = lb_[q] == ub_[q] ? kFixed : kInactive;
      link_[q] = kInactive;
    }
  }
  void prepare();
  // Bound `side` of position q follows from the constraints left of it.
  bool implied(int q, std::int8_t side) const { return (implied_[q] & (side == kUpper ? 2 : 1)) != 0; }
  void independent_marks();
  bool equality_solve();
  int assemble_segments();
  int assemble_box();
  int feasible_start();
  S multipliers(S& hx_scale);
  // After multipliers(): by how much the multiplier of position q's bound
  // (of link q) has the wrong sign (> 0: wrong; 0 when inactive or fixed).
  S bound_sign_error(int q) const {
    return bound_[q] == kLower ? offset_[q] : (bound_[q] == kUpper ? -offset_[q] : S(0));
  }
  S link_sign_error(int q) const { return link_[q] == kLower ? rhs_[q] : (link_[q] == kUpper ? -rhs_[q] : S(0)); }
  int ratio_test(S& alpha, int& kind, std::int8_t& side) const;
  bool final_check() const;
  int exchange_rounds(int rounds, int limit, int& changes, S dual_tol, S g_scale);
  // The chain's length, visibly at most L (for the compiler's bounds checks
  // as much as for the reader: gather() never makes it longer). A copy: the
  // stores to the marks (bytes) could alias ch_ as far as the compiler knows,
  // so ch_.n would be read again after each.
  int length() const { return n_ < L ? n_ : L; }
  S bound_value(int q, std::int8_t side) const { return side == kUpper ? ub_[q] : lb_[q]; }
  S link_value(int q, std::int8_t side) const { return side == kUpper ? ch_.link_hi[q] : ch_.link_lo[q]; }

  const ChainData<D, L>& ch_;
  const QpSettings<S>& s_;
  const int n_ = ch_.n < L ? ch_.n : L;
  S g_scale_ = S(1);     // max(1, max |g_q|)
  const bool linked_ = ch_.linked;  // the chain has link rows
  const S* const g_ = ch_.g;
  const S* const lb_ = ch_.lb;
  const S* const ub_ = ch_.ub;
  int factorisations_ = 0;
  std::int8_t bound_[kLz];       // per position
  std::int8_t link_[kLz];        // per link q -> q + 1
  std::int8_t guessed_bound_[kLz];  // a warm start's guess of bound_
  std::uint8_t implied_[kLz];    // per position: bit 0 its lower bound implied, bit 1 its upper
  std::int16_t free_first_[kLz];  // free segment f: its first position
  std::int16_t free_last_[kLz];   // and its last
  std::int16_t position_free_[kLz + 2];  // [q + 2]: free index of position q's segment, -1: held by a bound
  S x0_[kLz + 4];                // [q + 2]: x with every free y = 0; 0 outside the chain
  // o_q during a linked chain's equality solve; after it (multipliers()) the
  // bound multipliers
  S offset_[kLz];
  S x_padded_[kLz + 4] = {};     // [q + 2]: the feasible iterate, 0 outside the chain (ChainData::hx)
  S* const x_ = x_padded_ + 2;
  S xe_[kLz];                    // equality-constrained optimum for W
  S r_[kLz];                     // H x + g
  S band_[kLz][3];               // reduced Hessian, lower band (half-bandwidth 2), factored in place
  // During an equality solve Z'(-Hx0 - g), then y; after it the link
  // multipliers
  S rhs_[kLz];
};

// Before any solve: the marks cleared (W = the fixed variables), then in one
// pass the scale of g and the bounds implied by the constraints left of them,
// to rounding: lb_q <= (the least x_{q-1} can be) + link_lo + tol (1 +
// |lb_q|), and likewise above. The coarse QP's time chain has runs of them
// (its lower bounds a staircase of minimum steps, so a bound and the link
// beside it are tight together), and exchanging such a bound for that link
// costs an equality solve each time without moving x. An implied bound never
// enters the marks; final_check() still checks it. The reach is carried
// without the implied bounds, so x_q >= lb_q - tol (1 + |lb_q|) holds for
// each one, without accumulating. A chain without link rows implies none.
template <class D, int L>
void ChainSolver<D, L>::prepare() {
  const S tol = s_.primal_tolerance;
  const S inf = std::numeric_limits<S>::infinity();
  S reach_lo = -inf, reach_hi = inf;
  S g_scale = S(1);
  const bool linked = linked_;
  clear_marks();
  for (int q = 0; q < length(); ++q) {  // < L
    const S a = std::fabs(g_[q]);
    g_scale = a > g_scale ? a : g_scale;
    implied_[q] = 0;
    if (!linked) continue;
    const S lb = lb_[q], ub = ub_[q];
    const bool fixed = bound_[q] == kFixed;
    const int k = q > 0 ? q - 1 : 0;  // link q-1 (none at q = 0)
    const S from_lo = q > 0 ? reach_lo + ch_.link_lo[k] : -inf;
    const S from_hi = q > 0 ? reach_hi + ch_.link_hi[k] : inf;
    const bool lo_implied = q > 0 && !fixed && lb <= from_lo + tol * (S(1) + std::fabs(lb));
    const bool hi_implied = q > 0 && !fixed && ub >= from_hi - tol * (S(1) + std::fabs(ub));
    implied_[q] = static_cast<std::uint8_t>((lo_implied ? 1 : 0) | (hi_implied ? 2 : 0));
    reach_lo = lo_implied ? from_lo : (lb > from_lo ? lb : from_lo);
    reach_hi = hi_implied ? from_hi : (ub < from_hi ? ub : from_hi);
  }
  g_scale_ = g_scale;
}

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

// xe = argmin of the QP with every marked constraint as an equality: the
// reduced system Z'HZ y = -Z'(H x0 + g) assembled (x0: x with every free
// y = 0), factored and solved, then xe = x0 + Z y.
template <class D, int L>
bool ChainSolver<D, L>::equality_solve() {
  ++factorisations_;
  // The padding: x0 is 0 and no position free off the chain's ends.
  position_free_[0] = position_free_[1] = -1;
  x0_[0] = x0_[1] = x0_[length() + 2] = x0_[length() + 3] = S(0);
  const int free_count = linked_ ? assemble_segments() : assemble_box();
  if (free_count > 0) {
    if (!penta::factor(band_, band_, free_count)) return false;
    penta::solve(band_, free_count, rhs_);
  }
  const S* x0 = x0_ + 2;
  const std::int16_t* pf = position_free_ + 2;
  for (int q = 0; q < length(); ++q) {  // < L
    const int f = pf[q];
    xe_[q] = x0[q] + (f >= 0 ? rhs_[f] : S(0));
  }
  return true;
}

// The reduced system of a chain with link rows, in two passes: the segments
// (offsets, x0, free indices), then row f for one free segment a..b at a
// time. The row holds the couplings with earlier segments (the lower band);
// H being pentadiagonal, only a and a + 1 reach back out of the segment, to
// a - 1 and a - 2, and every later position adds its h0, 2 h1, 2 h2 to the
// diagonal. Each sum takes its terms in position order, as a
// position-by-position assembly would (the terms left out are exact zeros).
// Returns the number of free segments.
template <class D, int L>
int ChainSolver<D, L>::assemble_segments() {
  const int n = length();
  int free_count = 0;
  int first = 0;      // the open segment's first position
  S offset = S(0);    // o_q: the active link values from the segment's start
  S base = S(0);      // the segment's value at offset 0: bound value - o at its bound; 0 while free
  bool held = false;  // the segment has a bound
  for (int q = 0; q < n; ++q) {  // < L
    offset_[q] = offset;
    if (bound_[q] != kInactive) held = true, base = bound_value(q, bound_[q]) - offset;
    if (q + 1 < n && link_[q] != kInactive) {
      offset += link_value(q, link_[q]);
      continue;
    }
    // The segment first..q ends here.
    const std::int16_t f = held ? std::int16_t(-1) : static_cast<std::int16_t>(free_count);
    if (!held) {
      free_first_[free_count] = static_cast<std::int16_t>(first);
      free_last_[free_count] = static_cast<std::int16_t>(q);
      ++free_count;
    }
    const S value = held ? base : S(0);
    for (int k = first; k <= q; ++k) {  // < L in all: the segments partition the positions
      x0_[k + 2] = offset_[k] + value;
      position_free_[k + 2] = f;
    }
    first = q + 1;
    offset = S(0);
    held = false;
  }
  const S* h0 = ch_.h0();
  const S* h1 = ch_.h1();
  const S* h2 = ch_.h2();
  const S* x0 = x0_ + 2;                        // x0[-2], x0[-1], x0[n], x0[n+1] are 0
  const std::int16_t* pf = position_free_ + 2;  // pf[-2], pf[-1] are -1
  for (int f = 0; f < free_count; ++f) {  // < L
    const int a = free_first_[f];
    const int b = free_last_[f];
    // Couplings out of the segment: H(a, a-1) and H(a+1, a-1) with a free
    // a - 1 (segment f - 1), H(a, a-2) with a free a - 2 (f - 1 or f - 2).
    const int f1 = pf[a - 1];
    const int f2 = pf[a - 2];
    S d = h0[a];
    S e1 = S(0);
    S e2 = S(0);
    if (f1 >= 0) e1 += h1[a - 1];
    if (f2 >= 0 && f - f2 == 1) e1 += h2[a - 2];
    if (f2 >= 0 && f - f2 == 2) e2 += h2[a - 2];
    if (a < b) {
      d += h0[a + 1];
      d += S(2) * h1[a];
      if (f1 >= 0) e1 += h2[a - 1];
    }
    for (int q = a + 2; q <= b; ++q) {  // < L in all
      d += h0[q];
      d += S(2) * h1[q - 1];
      d += S(2) * h2[q - 2];
    }
    S r = S(0);
    for (int q = a; q <= b; ++q) {  // < L in all
      const S hx = ch_.hx(x0, q);
      r -= hx + g_[q];
    }
    band_[f][0] = d;
    band_[f][1] = e1;
    band_[f][2] = e2;
    rhs_[f] = r;
  }
  return free_count;
}

// The reduced system of a chain without link rows (a box): every segment
// is one position, x0 the bound values (0 where free), and Z'HZ is H's rows
// and columns of the free positions: free f at q couples with q - 1 and
// q - 2 where they are free (f - 1 and f - 1 or f - 2). One pass each.
// Returns the number of free positions.
template <class D, int L>
int ChainSolver<D, L>::assemble_box() {
  const int n = length();
  int free_count = 0;
  for (int q = 0; q < n; ++q) {  // < L
    const bool held = bound_[q] != kInactive;
    x0_[q + 2] = held ? S(0) + bound_value(q, bound_[q]) : S(0);  // o + value, as for a segment
    position_free_[q + 2] = held ? std::int16_t(-1) : static_cast<std::int16_t>(free_count);
    free_count += held ? 0 : 1;
  }
  const S* h0 = ch_.h0();
  const S* h1 = ch_.h1();
  const S* h2 = ch_.h2();
  const S* x0 = x0_ + 2;
  const std::int16_t* pf = position_free_ + 2;
  for (int q = 0; q < n; ++q) {  // < L
    const int f = pf[q];
    if (f < 0) continue;
    const bool free1 = pf[q - 1] >= 0;
    const bool free2 = pf[q - 2] >= 0;
    const S hx = ch_.hx(x0, q);
    band_[f][0] = h0[q];
    band_[f][1] = free1 ? h1[q - 1] : (free2 ? h2[q - 2] : S(0));
    band_[f][2] = free1 && free2 ? h2[q - 2] : S(0);
    rhs_[f] = S(0) - (hx + g_[q]);
  }
  return free_count;
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
  reach_lo[length() - 1] = lb_[length() - 1];
  reach_hi[length() - 1] = ub_[length() - 1];
  for (int q = length() - 2; q >= 0; --q) {  // < L
    const S lo = reach_lo[q + 1] - ch_.link_hi[q];
    const S hi = reach_hi[q + 1] - ch_.link_lo[q];
    reach_lo[q] = lo > lb_[q] ? lo : lb_[q];
    reach_hi[q] = hi < ub_[q] ? hi : ub_[q];
    if (!(reach_lo[q] <= reach_hi[q])) return -1;
  }
  if (!(reach_lo[length() - 1] <= reach_hi[length() - 1])) return -1;
  int moved = 0;
  for (int q = 0; q < length(); ++q) {  // < L
    S lo = reach_lo[q], hi = reach_hi[q];
    // By what x is clamped: 1 its bound, 2 the link, 0 a later constraint
    // (the reach); an implied bound is never the one, the link is.
    std::int8_t lo_by = lo == lb_[q] && !implied(q, kLower) ? std::int8_t(1) : std::int8_t(0);
    std::int8_t hi_by = hi == ub_[q] && !implied(q, kUpper) ? std::int8_t(1) : std::int8_t(0);
    if (q > 0) {
      const S a = x_[q - 1] + ch_.link_lo[q - 1];
      const S b = x_[q - 1] + ch_.link_hi[q - 1];
      if (a > lo || (implied(q, kLower) && lo == lb_[q])) lo = a, lo_by = 2;
      if (b < hi || (implied(q, kUpper) && hi == ub_[q])) hi = b, hi_by = 2;
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
    if (bound_[q] == kLower) x_[q] = lb_[q];
    if (bound_[q] == kUpper) x_[q] = ub_[q];
    moved += keep ? 0 : 1;
  }
  independent_marks();
  return moved;
}

// y_bound, y_link at x (= xe) from r = Hx + g, in one pass: the partial
// sums of r along each segment are the link multipliers, their total the
// bound's (negated); links right of the bound add it back. Returns the
// largest |sum_s r| of a free segment (0 in exact arithmetic); hx_scale:
// max |(Hx)_q|.
template <class D, int L>
typename D::Scalar ChainSolver<D, L>::multipliers(S& hx_scale) {
  S* y_bound = offset_;  // free once xe_ is formed
  S* y_link = rhs_;
  const S* x = x_;  // padded: x[-2], x[-1], x[n], x[n+1] are 0
  S residual = S(0);
  S scale = S(0);
  S partial = S(0);  // sum of r over the open segment so far
  int held = -1;     // the open segment's bound
  for (int q = 0; q < length(); ++q) {  // < L
    const S hx = ch_.hx(x, q);
    const S a = std::fabs(hx);
    scale = a > scale ? a : scale;
    const S r = hx + g_[q];
    r_[q] = r;
    partial += r;
    y_bound[q] = S(0);
    if (bound_[q] != kInactive) held = q;
    if (q + 1 < length() && link_[q] != kInactive) {
      y_link[q] = partial;
      continue;
    }
    // The segment ends at q: its bound takes -sum r, and so do the links from it on.
    y_link[q] = S(0);
    if (held >= 0) {
      const S y_held = -partial;
      y_bound[held] = y_held;
      for (int k = held; k < q; ++k) y_link[k] += y_held;  // < L in all
    } else if (!(std::fabs(partial) <= residual)) {
      residual = std::fabs(partial);  // NaN too
    }
    partial = S(0);
    held = -1;
  }
  hx_scale = scale;
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
    if (bound_[q] != kInactive || position_free_[q + 2] < 0) continue;
    const S p = xe_[q] - x_[q];
    if (p < S(0) && lb_[q] > -std::numeric_limits<S>::infinity() && !implied(q, kLower)) {
      const S t = (lb_[q] - x_[q]) / p;
      if (t < alpha) alpha = t, kind = 1, which = q, side = kLower;
    } else if (p > S(0) && ub_[q] < std::numeric_limits<S>::infinity() && !implied(q, kUpper)) {
      const S t = (ub_[q] - x_[q]) / p;
      if (t < alpha) alpha = t, kind = 1, which = q, side = kUpper;
    }
  }
  for (int q = 0; q + 1 < length(); ++q) {  // < L
    if (link_[q] != kInactive || ch_.link_row[q] < 0) continue;
    if (position_free_[q + 2] < 0 && position_free_[q + 3] < 0) continue;
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
    ok = ok && std::isfinite(v) && v >= lb_[q] - tol * (S(1) + std::fabs(lb_[q])) &&
         v <= ub_[q] + tol * (S(1) + std::fabs(ub_[q]));
    if (q + 1 < length() && ch_.link_row[q] >= 0) {
      const S d = x_[q + 1] - x_[q];
      const S scale = S(1) + std::fabs(x_[q + 1]) + std::fabs(x_[q]);
      ok = ok && d >= ch_.link_lo[q] - tol * scale && d <= ch_.link_hi[q] + tol * scale;
    }
  }
  return ok;
}

// Primal-dual exchange rounds (the primal-dual active-set method of
// Hintermueller, Ito and Kunisch, SIAM J. Optim. 13(3), 2002): solve for the
// marks, then at once drop every marked constraint whose multiplier has the
// wrong sign and mark every constraint the equality optimum violates. No
// feasible iterate is needed, so many constraints change per solve (the
// primal loop changes one per blocked step). `changes` counts one per round
// that changes the marks, up to `limit`. Returns 1: the marks stood (xe
// feasible, every sign right, x = xe optimal), 0: not settled within
// `rounds` solves or the limit, -1: an equality solve failed.
template <class D, int L>
int ChainSolver<D, L>::exchange_rounds(int rounds, int limit, int& changes, S dual_tol, S g_scale) {
  const S tol = s_.primal_tolerance;
  for (int round = 0; round < rounds; ++round) {  // < rounds (a constant)
    if (!equality_solve()) return -1;
    for (int q = 0; q < length(); ++q) x_[q] = xe_[q];  // < L
    S hx_scale = S(0);
    const S residual = multipliers(hx_scale);
    int changed = 0;
    for (int q = 0; q < length(); ++q) {  // < L
      const S v = xe_[q];
      if (bound_[q] == kLower || bound_[q] == kUpper) {
        if (bound_sign_error(q) > dual_tol) bound_[q] = kInactive, ++changed;
      } else if (bound_[q] == kInactive) {
        const S lb = lb_[q], ub = ub_[q];
        std::int8_t side = kInactive;
        if (v < lb - tol * (S(1) + std::fabs(lb)) && !implied(q, kLower)) side = kLower;
        if (v > ub + tol * (S(1) + std::fabs(ub)) && !implied(q, kUpper)) side = kUpper;
        if (side != kInactive) {
          // The violated bound replaces the links at q: were q's segment held
          // by another bound, independent_marks() would drop this one again.
          bound_[q] = side;
          if (q > 0 && link_[q - 1] != kInactive) link_[q - 1] = kInactive, ++changed;
          if (link_[q] != kInactive) link_[q] = kInactive, ++changed;
          ++changed;
          continue;
        }
      }
      if (q + 1 >= length() || ch_.link_row[q] < 0) continue;
      if (link_[q] != kInactive) {
        if (link_sign_error(q) > dual_tol) link_[q] = kInactive, ++changed;
      } else {
        const S d = xe_[q + 1] - v;
        const S scale = S(1) + std::fabs(xe_[q + 1]) + std::fabs(v);
        if (d < ch_.link_lo[q] - tol * scale) link_[q] = kLower, ++changed;
        else if (d > ch_.link_hi[q] + tol * scale) link_[q] = kUpper, ++changed;
      }
    }
    if (changed == 0) {
      const bool stationary = residual <= s_.stationarity_tolerance * (g_scale + hx_scale);
      return stationary && final_check() ? 1 : 0;
    }
    // One working-set change per round (iterations count equality solves'
    // worth of work: a round costs one, however many marks it changes).
    if (changes >= limit) return 0;
    ++changes;
    independent_marks();
  }
  return 0;
}

// The solve. A warm start first tries exchange rounds from its guess; a cold
// one (or a warm one they leave) clamps the unconstrained optimum feasible,
// tries exchange rounds from that start on a chain with link rows, and else
// runs the primal loop from it: step to the equality optimum of the marks or
// add the constraint that blocks the step; at an equality optimum drop the
// constraints whose multipliers have the wrong sign (see spread_limit).
template <class D, int L>
bool ChainSolver<D, L>::solve(int cap, int& iterations, bool from_guess) {
  if (length() < 1) return false;
  const S g_scale = g_scale_;
  const S dual_tol = s_.dual_tolerance * g_scale;
  const int start_changes = iterations;  // every phase counts against the one cap
  const bool linked = linked_;  // a chain with link rows (see exchange_rounds)
  if (from_guess) {
    // A warm start: exchange rounds from the guess (no feasible point
    // needed); what they leave is solved cold. On a box chain one round (more
    // would often cycle), and only for a guess of more than
    // kFilterOnlyBounds bounds: a smaller one costs the filtered cold start
    // below about as few equality solves when it is right, and nothing when
    // it is wrong (measured: docs/qp.md, "Chain solver").
    independent_marks();
    int guessed = 0;  // a box chain's guess: kept for the filter below, its bounds counted
    for (int q = 0; q < length() && !linked; ++q) {  // < L
      guessed_bound_[q] = bound_[q];
      guessed += bound_[q] == kLower || bound_[q] == kUpper ? 1 : 0;
    }
    const int rounds = linked ? kExchangeRounds : (guessed > kFilterOnlyBounds ? 1 : 0);
    const int settled = exchange_rounds(rounds, start_changes + cap, iterations, dual_tol, g_scale);
    if (settled != 0) return settled > 0;
    clear_marks();
  }
  if (!equality_solve()) return false;
  int moved = feasible_start();
  if (moved < 0) return false;
  if (from_guess && !linked) {
    // A box chain whose guess did not stand: of the bounds the clamped start
    // holds, only those the guess held too stay marked (x stays feasible, on
    // them). The others were the guess's to drop: dropped one per equality
    // solve by the primal loop, they cost most on a curve that touches its
    // bounds along a run (measured: docs/qp.md, "Chain solver").
    for (int q = 0; q < length(); ++q) {  // < L
      if (bound_[q] != kFixed && bound_[q] != guessed_bound_[q]) bound_[q] = kInactive;
    }
  }
  if (moved > 0 && linked) {
    const int settled = exchange_rounds(kExchangeRounds, start_changes + cap, iterations, dual_tol, g_scale);
    if (settled != 0) return settled > 0;
    // Not settled: back to the clamped start (solved again: one equality
    // solve, not a copy of the start on the stack).
    clear_marks();
    if (!equality_solve()) return false;
    moved = feasible_start();
    if (moved < 0) return false;
  }
  bool current = moved == 0;  // xe_ is still the equality optimum of the marks
  // Every wrong sign is dropped at once while their count falls from one
  // such drop to the next (a block-pivoting safeguard): at most L block drops,
  // then one per visit, the textbook rule.
  int spread_limit = 4 * L;
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
      ++iterations;
      continue;
    }
    for (int q = 0; q < length(); ++q) x_[q] = xe_[q];  // < L
    S hx_scale = S(0);
    const S residual = multipliers(hx_scale);
    S worst = dual_tol;  // the wrong sign by the most (one-per-visit rule)
    int drop = -1;
    bool drop_link = false;
    int wrong = 0;
    for (int q = 0; q < length(); ++q) {  // < L
      const S yb = bound_sign_error(q);
      const S yl = link_sign_error(q);
      if (yb > worst) worst = yb, drop = q, drop_link = false;
      if (yl > worst) worst = yl, drop = q, drop_link = true;
      wrong += (yb > dual_tol ? 1 : 0) + (yl > dual_tol ? 1 : 0);
    }
    if (drop < 0) {
      // Free segments: their equality solve made sum_s r = 0; a residual
      // beyond rounding means the reduced solve was inaccurate.
      if (!(residual <= s_.stationarity_tolerance * (g_scale + hx_scale))) return false;
      return final_check();
    }
    if (iterations - start_changes >= cap) return false;
    int dropped = 0;
    if (wrong > 1 && wrong < spread_limit) {
      spread_limit = wrong;
      for (int q = 0; q < length(); ++q) {  // < L
        const bool room = iterations - start_changes + dropped < cap;
        if (room && bound_sign_error(q) > dual_tol) bound_[q] = kInactive, ++dropped;
        const bool room_link = iterations - start_changes + dropped < cap;
        if (room_link && link_sign_error(q) > dual_tol) link_[q] = kInactive, ++dropped;
      }
    } else {
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
