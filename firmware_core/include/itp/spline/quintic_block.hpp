#pragma once
// One quintic block of a C2 spline, parameterised by its end states
//   x = (p0, v0, a0, p1, v1, a1): value, first and second derivative at the
// block's start (local coordinate 0) and end (local coordinate h).
// Neighbouring blocks share their knot states, so a spline built from these
// blocks is C2 by construction (the paper's link constraints (7)/(12) hold
// without being written) and its Hessians are banded.
//
// Everything here is exact polynomial algebra: the monomial coefficients
// c = M(h) x, rows that evaluate a derivative at a point, and the Gram
// matrices of the integrated squared derivatives (closed form, no quadrature).
#include <Eigen/Core>

#include "itp/config.hpp"

namespace itp::spline {

using Vector6 = Eigen::Matrix<Scalar, 6, 1>;
using Row6 = Eigen::Matrix<Scalar, 1, 6>;
using Matrix6 = Eigen::Matrix<Scalar, 6, 6>;

inline constexpr int kBlockStates = 6;    // (p0, v0, a0, p1, v1, a1)
inline constexpr int kMaxDerivative = 3;  // cost terms go up to the third derivative

// c = M x with value(τ) = Σ_k c_k τ^k for local τ in [0, h].
Matrix6 coefficient_map(Scalar h);

// Row r with r · x = d^k/dτ^k value at local τ (k = 0..3).
Row6 evaluate_row(Scalar h, Scalar tau, int derivative);

// G with xᵀ G x = ∫_0^h (d^k/dτ^k value)² dτ (k = 0..3).
Matrix6 gram(Scalar h, int derivative);

// Row r with r · x = ∫_0^h value(τ) (r0 + r1 τ) dτ: the linear term of a
// squared deviation from a reference that is linear inside the block.
// With `derivative` = k: r · x = ∫_0^h (d^k/dτ^k value)(τ) (r0 + r1 τ) dτ.
Row6 linear_moment(Scalar h, Scalar r0, Scalar r1, int derivative = 0);

// Row r with r · x = ∫_a^b value(τ) dτ for 0 <= a <= b <= h: the linear term
// of a squared deviation from a reference that is constant on [a, b].
Row6 integral_row(Scalar h, Scalar a, Scalar b);

// d^k/dτ^k of Σ c_i τ^i at τ (k = 0..3), by Horner's rule: the cheap way to
// evaluate a solved spline once its blocks' coefficients are known.
Scalar eval_monomial(const Scalar* c, Scalar tau, int derivative);

// A solved spline of `blocks` blocks of length h from `origin`: per block the
// 6 monomial coefficients (from the 3 knot states of each end) ...
void block_coefficients(Scalar h, const Scalar* knots, int blocks, Scalar* coefficients);
// ... and its k-th derivative at x, clamped to [origin, origin + blocks h].
Scalar eval_spline(const Scalar* coefficients, int blocks, Scalar h, Scalar origin, Scalar x, int derivative);

}  // namespace itp::spline
