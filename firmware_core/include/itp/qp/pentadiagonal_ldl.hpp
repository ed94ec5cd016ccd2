#pragma once
// LDL' factor and solve of a symmetric pentadiagonal matrix (half-bandwidth
// 2), the reduced Hessian of the chain solver (chain_solver.hpp). Written out
// for this one bandwidth, without square roots, and with 1 / D stored, so a
// row costs one division and ~15 flops:
//   L(i,i-2) = A(i,i-2) / D(i-2)
//   L(i,i-1) = (A(i,i-1) - L(i,i-2) D(i-2) L(i-1,i-2)) / D(i-1)
//   D(i)     = A(i,i) - L(i,i-2)^2 D(i-2) - L(i,i-1)^2 D(i-1)
#include <cstddef>
#include <limits>

namespace itp::qp::penta {

// a[i] = {A(i,i), A(i,i-1), A(i,i-2)} (entries before row 0 ignored). Writes
// f[i] = {1 / D(i), L(i,i-1), L(i,i-2)}. False if a pivot is not safely
// positive (A not positive definite to working precision, or NaN).
template <typename S, std::size_t W>
bool factor(const S (*a)[W], S (*f)[W], int n) {
  static_assert(W == 3, "three diagonals");
  const S rel = S(10) * std::numeric_limits<S>::epsilon();
  S d1 = S(0), d2 = S(0);    // D(i-1), D(i-2)
  S l1_prev = S(0);          // L(i-1, i-2)
  for (int i = 0; i < n; ++i) {  // < n rows
    const S l2 = i >= 2 ? a[i][2] * f[i - 2][0] : S(0);
    const S l1 = i >= 1 ? (a[i][1] - l2 * d2 * l1_prev) * f[i - 1][0] : S(0);
    const S d = a[i][0] - l2 * l2 * d2 - l1 * l1 * d1;
    if (!(d > rel * a[i][0])) return false;
    f[i][0] = S(1) / d;
    f[i][1] = l1;
    f[i][2] = l2;
    d2 = d1;
    d1 = d;
    l1_prev = l1;
  }
  return true;
}

// Solves A y = b in place with the factor of factor().
template <typename S, std::size_t W>
void solve(const S (*f)[W], int n, S* b) {
  static_assert(W == 3, "three diagonals");
  S z1 = S(0), z2 = S(0);
  for (int i = 0; i < n; ++i) {  // < n: L z = b
    const S z = b[i] - f[i][1] * z1 - f[i][2] * z2;
    b[i] = z;
    z2 = z1;
    z1 = z;
  }
  S y1 = S(0), y2 = S(0);  // y(i+1), y(i+2)
  for (int i = n - 1; i >= 0; --i) {  // < n: D L' y = z
    const S l1_next = i + 1 < n ? f[i + 1][1] : S(0);  // L(i+1, i)
    const S l2_next = i + 2 < n ? f[i + 2][2] : S(0);  // L(i+2, i)
    const S y = b[i] * f[i][0] - l1_next * y1 - l2_next * y2;
    b[i] = y;
    y2 = y1;
    y1 = y;
  }
}

}  // namespace itp::qp::penta
