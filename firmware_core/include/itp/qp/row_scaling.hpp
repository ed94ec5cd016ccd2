#pragma once
// Safe row norms and exact row scaling (issue 13, defect 4).
//
// The violation of row r is ranked by (a'x - b) / |a|, and the row enters the
// transformed problem as m = L^-1 a with |m|^2 in the Gram matrix K = M_W M_W'.
// Summing a_k^2 directly overflows for |a| above ~1e154 (and underflows below
// ~1e-154): the old code then took 1/sqrt(inf) = 0 as the row's scale, ranked
// every violation of the row as 0 and never added it, so x violated it and
// was still called optimal.
//
// Two remedies, both exact for the rows the planner builds:
// - row_inverse_norm() sums a_k^2 as before when that sum is a normal number
//   well inside the range (bit-identical to the old result), and otherwise
//   rescales by the largest |a_k| first:  |a| = amax sqrt(sum (a_k/amax)^2).
// - row_power() is 1 for rows whose norm lies in [2^-E, 2^E] (E = 16 in
//   double, 8 in float) and otherwise the power of two that brings |a| into
//   (1/2, 1]. Multiplying a row and its bounds by a power of two is exact in
//   binary floating point (no rounding), and  2^k lb <= 2^k a'x <= 2^k ub  is
//   the same set; its multiplier is 2^-k times the original row's, which the
//   solver undoes when it reports y. Why a narrow E: the dual loop compares
//   multipliers with an absolute tolerance and mixes all rows in one Gram
//   matrix K, so rows of wildly different norms (|a| 2^-500 next to 2^500)
//   make near-zero multipliers look non-negative and products underflow;
//   within 2^+-16 neither happens. The planner's rows (norms 0.5..40) are
//   never touched, so its results stay bit-identical.
#include <cmath>
#include <limits>

namespace itp::qp::rows {

// Row norms in [2^-E, 2^E] enter unscaled.
template <typename S>
constexpr int kSafeExponent = std::numeric_limits<S>::digits > 24 ? 16 : 8;
// A sum of squares in [2^-F, 2^F] lost nothing to overflow or underflow.
template <typename S>
constexpr int kPlainSumExponent = std::numeric_limits<S>::max_exponent / 2;

// 1 / |a|_2 of `count` values outside the plain range: rescaled by the
// largest |a_k| first (1 for a zero row).
template <typename S>
S rescaled_inverse_norm(const S* values, int count) {
  S amax = S(0);
  for (int k = 0; k < count; ++k) {
    const S a = std::abs(values[k]);
    if (a > amax) amax = a;
  }
  if (!(amax > S(0))) return S(1);
  // amax is rescaled to 1 by an exact power of two, so the sum stays in range.
  const S pw = std::ldexp(S(1), -std::ilogb(amax));
  S s2 = S(0);
  for (int k = 0; k < count; ++k) {
    const S v = values[k] * pw;
    s2 += v * v;
  }
  return pw / std::sqrt(s2);
}

// 1 / |a|_2 of `count` values whose sum of squares, summed in k order, is
// n2 (1 for a zero row: its violation |b| is then ranked unscaled, and adding
// it yields a dependent row, i.e. a dual ray). The values are read again only
// when n2 lies outside the plain range.
template <typename S>
inline S inverse_norm_of_sum(S n2, const S* values, int count) {
  const S lo = std::ldexp(S(1), -kPlainSumExponent<S>);
  const S hi = std::ldexp(S(1), kPlainSumExponent<S>);
  if (n2 >= lo && n2 <= hi) return S(1) / std::sqrt(n2);
  return rescaled_inverse_norm(values, count);
}

// 1 / |a|_2 of `count` values (inverse_norm_of_sum).
template <typename S>
S row_inverse_norm(const S* values, int count) {
  S n2 = S(0);
  for (int k = 0; k < count; ++k) n2 += values[k] * values[k];
  return inverse_norm_of_sum(n2, values, count);
}

// Power of two p with p |a| near 1 when |a| = 1/inverse_norm lies outside
// [2^-E, 2^E]; exactly 1 otherwise (the common case: no arithmetic changes).
template <typename S>
S row_power(S inverse_norm) {
  const S lo = std::ldexp(S(1), -kSafeExponent<S>);
  const S hi = std::ldexp(S(1), kSafeExponent<S>);
  if (inverse_norm >= lo && inverse_norm <= hi) return S(1);
  if (!(inverse_norm > S(0)) || !(inverse_norm < std::numeric_limits<S>::infinity())) return S(1);
  int e = std::ilogb(inverse_norm);
  const int emax = std::numeric_limits<S>::max_exponent - 2;
  if (e > emax) e = emax;
  if (e < -emax) e = -emax;
  return std::ldexp(S(1), e);
}

}  // namespace itp::qp::rows
