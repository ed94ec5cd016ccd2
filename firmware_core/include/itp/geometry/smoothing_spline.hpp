#pragma once
// Natural cubic smoothing spline (Reinsch 1967; Green & Silverman 1994, ch. 2)
// through knots t_0 < ... < t_{n-1}, fitted to two coordinates at once (x(t)
// and y(t) share the knots and the penalty):
//
//   minimise  sum_i w_i (y_i - g(t_i))^2 + lambda * integral g''(t)^2 dt
//
// The minimiser is a natural cubic spline with values g_i and second
// derivatives gamma_i at the knots (gamma_0 = gamma_{n-1} = 0). With Q the
// n x (n-2) second-difference matrix and R the (n-2) x (n-2) tridiagonal
// Gram matrix of the hat functions,
//
//   (R + lambda Q^T W^-1 Q) gamma = Q^T y,    g = y - lambda W^-1 Q gamma.
//
// The system matrix is symmetric positive definite and pentadiagonal; it is
// factored once (banded LDL^T, O(n)) and solved for x and y. lambda = 0 gives
// the interpolating natural cubic spline.
#include <span>

#include "itp/config.hpp"

namespace itp::geometry {

// Scratch memory for one fit; every array has Cfg::kMaxReferenceKnots entries.
template <class Cfg>
struct BasicSmoothingSplineWorkspace {
  Scalar d[Cfg::kMaxReferenceKnots];    // LDL^T diagonal D
  Scalar l1[Cfg::kMaxReferenceKnots];   // L sub-diagonal (i, i-1)
  Scalar l2[Cfg::kMaxReferenceKnots];   // L second sub-diagonal (i, i-2)
  Scalar a1[Cfg::kMaxReferenceKnots];   // system matrix (i, i+1)
  Scalar a2[Cfg::kMaxReferenceKnots];   // system matrix (i, i+2)
  Scalar rhs[Cfg::kMaxReferenceKnots];  // right-hand side, then solution
};

// Fits one coordinate. t, w, y: n knots, weights [-] (> 0) and data [m];
// outputs g (fitted values [m]) and gamma (second derivatives d2g/dt2 [1/m]),
// n entries each. Requires 3 <= n <= Cfg::kMaxReferenceKnots and strictly
// increasing t. Returns false if the system is not positive definite
// (numerically degenerate knots).
template <class Cfg>
bool fit_smoothing_spline(std::span<const Scalar> t, std::span<const Scalar> w,
                          std::span<const Scalar> y, Scalar lambda,
                          BasicSmoothingSplineWorkspace<Cfg>& ws, std::span<Scalar> g,
                          std::span<Scalar> gamma);

using SmoothingSplineWorkspace = BasicSmoothingSplineWorkspace<DefaultConfig>;

}  // namespace itp::geometry
