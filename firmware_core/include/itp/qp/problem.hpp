#pragma once
// QP data in the qpOASES standard form
//   min 1/2 x'Hx + g'x   s.t.  lbA <= A x <= ubA,  lb <= x <= ub
// with H banded (lower band stored) and A row-sparse (fixed nonzeros per row).
// Plain data owned by the caller (static storage); nothing allocates.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "itp/qp/banded_cholesky.hpp"
#include "itp/qp/dimensions.hpp"

namespace itp::qp {

template <class D>
struct QpProblem {
  using S = typename D::Scalar;
  static constexpr int kN = D::kMaxVariables;
  static constexpr int kM = D::kMaxRows;
  static constexpr int kNnz = D::kMaxRowNonzeros;
  static constexpr int kBw = D::kBandwidth;
  // Array extents (size_t) derived from the capacities.
  static constexpr std::size_t kNz = static_cast<std::size_t>(kN);
  static constexpr std::size_t kMz = static_cast<std::size_t>(kM > 0 ? kM : 1);
  static constexpr std::size_t kNnzz = static_cast<std::size_t>(kNnz);
  static constexpr std::size_t kBandz = static_cast<std::size_t>(kBw + 1);

  int n = 0;  // variables in use, 1..kN
  int m = 0;  // constraint rows in use, 0..kM
  // Lower band of H: h_band[i][k] = H(i, i - k), k = 0..kBw (k = 0: diagonal).
  // Entries with i - k < 0 are ignored.                      [kN x (kBw+1)]
  S h_band[kNz][kBandz];
  S g[kNz];                 // linear cost                       [kN]
  // Row-sparse A: row r has a_nnz[r] entries, columns strictly increasing.
  using ColumnIndex = typename D::ColumnIndex;  // std::uint8_t for N <= 255
  ColumnIndex a_nnz[kMz];                //             [kM]
  ColumnIndex a_col[kMz][kNnzz];         //             [kM x kNnz]
  S a_val[kMz][kNnzz];                   //             [kM x kNnz]
  S lba[kMz];   // row lower bounds, may be -inf      [kM]
  S uba[kMz];   // row upper bounds, may be +inf      [kM]
  S lb[kNz];                 // variable lower bounds, may be -inf [kN]
  S ub[kNz];                 // variable upper bounds, may be +inf [kN]

  // Sets the sizes and clears all data: H = 0, g = 0, rows empty and
  // unbounded, variables unbounded. Returns false if beyond capacity.
  bool reset(int n_vars, int m_rows) {
    if (n_vars < 1 || n_vars > kN || m_rows < 0 || m_rows > kM) {
      return false;
    }
    n = n_vars;
    m = m_rows;
    const S inf = std::numeric_limits<S>::infinity();
    for (int i = 0; i < kN; ++i) {
      for (int k = 0; k <= kBw; ++k) h_band[i][k] = S(0);
      g[i] = S(0);
      lb[i] = -inf;
      ub[i] = inf;
    }
    for (int r = 0; r < (kM > 0 ? kM : 1); ++r) {
      a_nnz[r] = 0;
      for (int k = 0; k < kNnz; ++k) {
        a_col[r][k] = 0;
        a_val[r][k] = S(0);
      }
      lba[r] = -inf;
      uba[r] = inf;
    }
    return true;
  }

  // H(i, j) (symmetric). Returns false if (i, j) lies outside the band.
  bool set_hessian(int i, int j, S value) {
    if (i < j) {
      const int t = i;
      i = j;
      j = t;
    }
    if (j < 0 || i >= n || i - j > kBw) return false;
    h_band[i][i - j] = value;
    return true;
  }
  S hessian(int i, int j) const {
    if (i < j) {
      const int t = i;
      i = j;
      j = t;
    }
    if (j < 0 || i >= n || i - j > kBw) return S(0);
    return h_band[i][i - j];
  }

  // Appends entry (col, value) to row r; columns must be added in increasing
  // order. Returns false when the row is full or the column out of order.
  bool push_row_entry(int r, int col, S value) {
    if (r < 0 || r >= m || col < 0 || col >= n) return false;
    const int k = a_nnz[r];
    if (k >= kNnz || (k > 0 && a_col[r][k - 1] >= col)) return false;
    a_col[r][k] = static_cast<ColumnIndex>(col);
    a_val[r][k] = value;
    a_nnz[r] = static_cast<ColumnIndex>(k + 1);
    return true;
  }

  // a_r' x
  S row_dot(int r, const S* x) const {
    S s = S(0);
    for (int k = 0; k < a_nnz[r]; ++k) s += a_val[r][k] * x[a_col[r][k]];
    return s;
  }
};

// 1/2 x'Hx + g'x; hx (n scalars) receives Hx.
template <class D>
typename D::Scalar objective_value(const QpProblem<D>& p, const typename D::Scalar* x, typename D::Scalar* hx) {
  using S = typename D::Scalar;
  band::multiply(p.h_band, p.n, x, hx);
  S obj = S(0);
  for (int j = 0; j < p.n; ++j) obj += x[j] * (S(0.5) * hx[j] + p.g[j]);  // < N
  return obj;
}

// The vector data a hotstart may change: g finite; bounds not NaN, lb <= ub,
// lbA <= ubA, no lower bound of +inf and no upper bound of -inf.
template <class D>
bool is_valid_vectors(const QpProblem<D>& p) {
  using S = typename D::Scalar;
  if (p.n < 1 || p.n > D::kMaxVariables || p.m < 0 || p.m > D::kMaxRows) return false;
  const S inf = std::numeric_limits<S>::infinity();
  // Branch-light (this runs on every solve, hotstarts included): a value v is
  // finite iff v * 0 == 0, so one NaN-propagating sum checks all of g, and
  // !(lo <= hi) also catches a NaN bound.
  bool ok = true;
  S zero_sum = S(0);
  for (int i = 0; i < p.n; ++i) {
    const S lo = p.lb[i], hi = p.ub[i];
    zero_sum += p.g[i] * S(0);
    ok = ok & (lo <= hi) & (lo != inf) & (hi != -inf);
  }
  for (int r = 0; r < p.m; ++r) {
    const S lo = p.lba[r], hi = p.uba[r];
    ok = ok & (lo <= hi) & (lo != inf) & (hi != -inf);
  }
  return ok && zero_sum == S(0);
}

// H's band finite: a value v is finite iff v * 0 == 0 (inf * 0 and NaN * 0
// are NaN), so one NaN-propagating sum checks the band.
template <class D>
bool hessian_finite(const QpProblem<D>& p) {
  using S = typename D::Scalar;
  S zero_sum = S(0);
  for (int i = 0; i < p.n; ++i) {
    for (int k = 0; k <= D::kBandwidth && k <= i; ++k) zero_sum += p.h_band[i][k] * S(0);
  }
  return zero_sum == S(0);
}

// The rows of A: nnz within capacity, columns strictly increasing in
// 0..n-1, values finite. With kSumSquares also each row's sum_k a_k^2, into
// sum_sq[r] (M scalars; summed in k order, as rows::row_inverse_norm sums
// it), so that the solver's row scaling needs no second pass over A.
template <class D, bool kSumSquares = false>
bool rows_valid(const QpProblem<D>& p, typename D::Scalar* sum_sq = nullptr) {
  using S = typename D::Scalar;
  // Strictly increasing columns lie in 0..n-1 iff the first is >= 0 and the
  // last < n, so the range is tested once per row. The values: a finite sum
  // of squares proves them finite (NaN and inf propagate); only a row whose
  // sum is not finite (a value of 1e200 overflows it) is tested value by
  // value, v finite iff v * 0 == 0.
  bool ok = true;
  for (int r = 0; r < p.m; ++r) {
    const int nnz = p.a_nnz[r];
    if (nnz < 0 || nnz > D::kMaxRowNonzeros) return false;
    const typename D::ColumnIndex* col = p.a_col[r];
    const S* val = p.a_val[r];
    S n2 = S(0);
    if (nnz > 0) {
      ok = ok & (static_cast<int>(col[0]) >= 0) & (col[nnz - 1] < p.n);
      n2 += val[0] * val[0];
    }
    for (int k = 1; k < nnz; ++k) {
      ok = ok & (col[k] > col[k - 1]);
      n2 += val[k] * val[k];
    }
    if (!(n2 <= std::numeric_limits<S>::max())) {
      S zero_sum = S(0);
      for (int k = 0; k < nnz; ++k) zero_sum += val[k] * S(0);
      if (!(zero_sum == S(0))) return false;
    }
    if constexpr (kSumSquares) sum_sq[r] = n2;
  }
  return ok;
}

// kInvalidInput conditions: sizes beyond capacity, NaN/Inf in H, g or A, NaN
// bounds, lb > ub, lbA > ubA, a lower bound of +inf or an upper bound of -inf,
// bad column indices (out of range or not strictly increasing).
template <class D>
bool is_valid(const QpProblem<D>& p) {
  return is_valid_vectors(p) && hessian_finite(p) && rows_valid(p);
}

// is_valid(), also giving each row's sum of squares in sum_sq (M scalars,
// rows_valid), for the solver's row scaling.
template <class D>
bool is_valid(const QpProblem<D>& p, typename D::Scalar* sum_sq) {
  return is_valid_vectors(p) && hessian_finite(p) && rows_valid<D, true>(p, sum_sq);
}

}  // namespace itp::qp
