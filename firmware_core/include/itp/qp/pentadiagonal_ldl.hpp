#pragma once
// LDL' factor and solve of a symmetric pentadiagonal matrix (half-bandwidth
// 2), the reduced Hessian of the chain solver (chain_solver.hpp). Written out
// for this one bandwidth, without square roots, and with 1 / D stored, so a
// row costs one division and ~12 flops. With e(i) = L(i,i-1) D(i-1):
//   L(i,i-2) = A(i,i-2) / D(i-2)            (so L(i,i-2) D(i-2) = A(i,i-2))
//   e(i)     = A(i,i-1) - A(i,i-2) L(i-1,i-2)
//   D(i)     = A(i,i) - L(i,i-2) A(i,i-2) - e(i)^2 / D(i-1),   L(i,i-1) = e(i) / D(i-1)
// Rows are a chain of dependences through 1 / D(i-1); this form puts only
// the division, one product and one difference on it (the rest waits off
// the chain), and the sweeps of solve() likewise one product and one
// difference per row.
#include <cstddef>
#include <limits>

namespace itp::qp::penta {

// a[i] = {A(i,i), A(i,i-1), A(i,i-2)} (entries before row 0 ignored). Writes
// f[i] = {1 / D(i), L(i,i-1), L(i,i-2)}; f may be a (row i of a is read
// before row i of f is written). False if a pivot is not safely positive (A
// not positive definite to working precision, or NaN).
template <typename S, std::size_t W>
bool factor(const S (*a)[W], S (*f)[W], int n) {
  static_assert(W == 3, "three diagonals");
  const S rel = S(10) * std::numeric_limits<S>::epsilon();
  S inv1 = S(0), inv2 = S(0);  // 1 / D(i-1), 1 / D(i-2), kept in registers
  S l1_prev = S(0);            // L(i-1, i-2)
  // Rows 0 and 1 have no L(i, i-2) (nor row 0 an L(i, i-1)): peeled, so the
  // loop below needs no tests.
  for (int i = 0; i < n && i < 2; ++i) {  // <= 2 rows
    const S e = i == 1 ? a[1][1] : S(0);
    const S d = a[i][0] - (e * e) * inv1;
    if (!(d > rel * a[i][0])) return false;
    const S l1 = e * inv1;
    inv2 = inv1;
    inv1 = S(1) / d;
    f[i][0] = inv1;
    f[i][1] = l1;
    f[i][2] = S(0);
    l1_prev = l1;
  }
  for (int i = 2; i < n; ++i) {  // < n rows
    const S l2 = a[i][2] * inv2;
    const S e = a[i][1] - a[i][2] * l1_prev;
    const S d = (a[i][0] - l2 * a[i][2]) - (e * e) * inv1;
    if (!(d > rel * a[i][0])) return false;
    const S l1 = e * inv1;
    inv2 = inv1;
    inv1 = S(1) / d;
    f[i][0] = inv1;
    f[i][1] = l1;
    f[i][2] = l2;
    l1_prev = l1;
  }
  return true;
}

// Solves A y = b in place with the factor of factor().
template <typename S, std::size_t W>
void solve(const S (*f)[W], int n, S* b) {
  static_assert(W == 3, "three diagonals");
  S z1 = S(0), z2 = S(0);
  for (int i = 0; i < n; ++i) {  // < n: L z = b (f[0][1..2], f[1][2] are 0)
    const S z = (b[i] - f[i][2] * z2) - f[i][1] * z1;
    b[i] = z;
    z2 = z1;
    z1 = z;
  }
  // D L' y = z from the last row up; the last two rows (no L(i+2, i), the
  // last no L(i+1, i)) peeled, so the loop needs no tests.
  S y1 = S(0), y2 = S(0);  // y(i+1), y(i+2)
  if (n >= 1) {
    y1 = b[n - 1] * f[n - 1][0];
    b[n - 1] = y1;
  }
  if (n >= 2) {
    const S y = b[n - 2] * f[n - 2][0] - f[n - 1][1] * y1;
    b[n - 2] = y;
    y2 = y1;
    y1 = y;
  }
  for (int i = n - 3; i >= 0; --i) {  // < n
    const S y = (b[i] * f[i][0] - f[i + 2][2] * y2) - f[i + 1][1] * y1;
    b[i] = y;
    y2 = y1;
    y1 = y;
  }
}

}  // namespace itp::qp::penta
