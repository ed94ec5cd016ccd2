#pragma once
// Banded Cholesky H = L L' and the triangular solves with L, all in the lower
// band layout band[i][k] = X(i, i - k), k = 0..Bw. The factor stores the
// RECIPROCAL of its diagonal, l[i][0] = 1 / L(i,i), so that the solves
// multiply instead of divide (a division's latency would sit on the solves'
// critical path). Cost: factor n(Bw+1)^2
// flops (O(n Bw^2)); each solve 2 n (Bw+1) flops (fewer from a start index).
//
//   L(i,j) = ( H(i,j) - sum_{k=max(0,i-Bw)}^{j-1} L(i,k) L(j,k) ) / L(j,j),  j < i
//   L(j,j) = sqrt( H(j,j) - sum_k L(j,k)^2 )
#include <cmath>
#include <cstddef>
#include <limits>

namespace itp::qp::band {

// Factorises the n x n band matrix h (lower band, half-bandwidth Bw) into l.
// A diagonal shift `reg` >= 0 is added to H first (the proximal weight of a
// semidefinite H, hessian_factor.hpp; 0 otherwise). Returns -1 on success, or
// the row i whose pivot is not safely positive (H + reg I is not positive
// definite to working precision). Then rows 0..i-1 of l hold the factor of the
// leading i x i block and row i its off-diagonal part L(i, 0..i-1), from which
// hessian_factor.hpp builds a test direction.
template <typename S, std::size_t W>
int cholesky_failing_row(const S (*h)[W], S (*l)[W], int n, S reg) {
  constexpr int Bw = static_cast<int>(W) - 1;
  // A pivot below (Bw + 8) eps |H(i,i) + reg| is rounding noise of a zero
  // pivot: H is singular to working precision (semidefinite -> kNotConvex).
  const S rel = static_cast<S>(Bw + 8) * std::numeric_limits<S>::epsilon();
  for (int i = 0; i < n; ++i) {
    const int j0 = i - Bw > 0 ? i - Bw : 0;
    for (int j = j0; j <= i; ++j) {
      S s = h[i][i - j] + (i == j ? reg : S(0));
      for (int k = j0; k < j; ++k) s -= l[i][i - k] * l[j][j - k];
      if (i == j) {
        if (!(s > rel * std::abs(h[i][0] + reg))) return i;  // also catches NaN
        l[i][0] = S(1) / std::sqrt(s);
      } else {
        l[i][i - j] = s * l[j][0];
      }
    }
  }
  return -1;
}

template <typename S, std::size_t W>
bool cholesky(const S (*h)[W], S (*l)[W], int n, S reg) {
  return cholesky_failing_row(h, l, n, reg) < 0;
}

// A factor whose entries at odd band offsets are all zero: H couples only
// variables of equal index parity (two interleaved chains, as in the coarse
// QP's (l_i, t_i)), and then so does L, exactly (every term of an odd-offset
// entry has one factor at an odd offset, by induction). The solves below with
// Stride = 2 skip those zero terms and take the others in the original order,
// so for finite entries they give bit-identical results at half the flops (a
// skipped term l * b is a zero, and s - (+-0) = s for the sums here, which
// start from a row value and never become -0 by cancellation).
template <typename S, std::size_t W>
bool odd_offsets_zero(const S (*h)[W], int n) {
  constexpr int Bw = static_cast<int>(W) - 1;
  if (Bw < 2) return false;
  bool zero = true;
  for (int i = 0; i < n; ++i) {
    for (int k = 1; k <= Bw; k += 2) zero = zero & !(k <= i && h[i][k] != S(0));
  }
  return zero;
}

// Solves L y = b in place (y overwrites b). Entries b[0..start-1] must be zero
// and stay zero, so the solve starts at `start` (sparse right-hand sides).
// Stride 2: only the even band offsets (a factor with odd_offsets_zero).
template <int Stride = 1, typename S, std::size_t W>
void forward_solve(const S (*l)[W], int n, S* b, int start) {
  static_assert(Stride == 1 || Stride == 2, "every band offset, or the even ones");
  constexpr int Bw = static_cast<int>(W) - 1;
  // Rows start..start+Bw-1 see fewer than Bw earlier entries; the rest run a
  // loop of compile-time length Bw (unrolled). Same operation order as one loop.
  const int head_end = start + Bw < n ? start + Bw : n;
  for (int i = start; i < head_end; ++i) {
    S s = b[i];
    // nearest term last: only it waits for the previous row's result
    for (int k = start + (i - start) % Stride; k < i; k += Stride) s -= l[i][i - k] * b[k];
    b[i] = s * l[i][0];
  }
  for (int i = head_end; i < n; ++i) {
    S s = b[i];
    const S* li = l[i];
    for (int k = i - Bw + Bw % Stride; k < i; k += Stride) s -= li[i - k] * b[k];
    b[i] = s * li[0];
  }
}

// Solves L' x = y in place (x overwrites y). Stride as in forward_solve.
template <int Stride = 1, typename S, std::size_t W>
void backward_solve(const S (*l)[W], int n, S* y) {
  static_assert(Stride == 1 || Stride == 2, "every band offset, or the even ones");
  constexpr int Bw = static_cast<int>(W) - 1;
  // Rows n-Bw..n-1 see fewer than Bw later entries; rows below run a loop of
  // compile-time length Bw (unrolled). Same operation order as one loop.
  const int tail_begin = n - Bw > 0 ? n - Bw : 0;
  for (int i = n - 1; i >= tail_begin; --i) {
    S s = y[i];
    // farthest term first: only the last one waits for the previous row
    for (int k = n - 1 - (n - 1 - i) % Stride; k > i; k -= Stride) s -= l[k][k - i] * y[k];
    y[i] = s * l[i][0];
  }
  for (int i = tail_begin - 1; i >= 0; --i) {
    S s = y[i];
    for (int k = i + Bw - Bw % Stride; k > i; k -= Stride) s -= l[k][k - i] * y[k];
    y[i] = s * l[i][0];
  }
}

// y = H x for the symmetric band matrix h.
template <typename S, std::size_t W>
void multiply(const S (*h)[W], int n, const S* x, S* y) {
  constexpr int Bw = static_cast<int>(W) - 1;
  for (int i = 0; i < n; ++i) y[i] = S(0);
  for (int i = 0; i < n; ++i) {
    y[i] += h[i][0] * x[i];
    const int j0 = i - Bw > 0 ? i - Bw : 0;
    for (int j = j0; j < i; ++j) {
      y[i] += h[i][i - j] * x[j];
      y[j] += h[i][i - j] * x[i];
    }
  }
}

}  // namespace itp::qp::band
