#pragma once
// Chain form of a QP (docs/qp.md, "Chain solver"). The variables split into
// K interleaved chains (K = 1 or 2; x_j lies on chain j mod K at position
// j / K); H couples only neighbours at most two places apart on one chain,
// and every row is a link v (x_{j+K} - x_j), v > 0, between neighbours, at
// most one per link. The coarse decision QP has this form with K = 2: l_i and
// t_i, H of second differences, the monotone-time rows linking t_i to t_{i+1}.
//
// One chain's data is gathered into a ChainData: H as three diagonals, the
// link bounds in x units (lbA / v, ubA / v), and the row behind each link.
#include <cstddef>
#include <cstdint>
#include <limits>

#include "itp/qp/problem.hpp"

namespace itp::qp::chain {

inline constexpr int kMaxStride = 2;  // K: one chain, or two interleaved ones

// Variable j's chain (j mod K) and position on it (j / K), for K <= 2
// without a division (an integer division costs tens of cycles).
inline int chain_of(int j, int k) { return k == 2 ? (j & 1) : 0; }
inline int position_of(int j, int k) { return k == 2 ? (j >> 1) : j; }
static_assert(kMaxStride == 2, "chain_of / position_of are written for K <= 2");

// The stride K if `p` is in chain form with chains of at most `max_length`
// positions, else 0. `seen` (N bytes) is scratch: the links that have a row.
// In chain form A is valid too (finite, columns in range and increasing), and
// H off the chains' pattern is 0 (finite): with gather()'s test of the
// pattern, is_valid() holds without its own pass (solve_chain).
template <class D>
int find_stride(const QpProblem<D>& p, int max_length, std::uint8_t* seen) {
  using S = typename D::Scalar;
  static_assert(D::kMaxRowNonzeros >= 2, "a link row has two nonzeros");
  const S inf = std::numeric_limits<S>::infinity();
  for (int k = 1; k <= kMaxStride; ++k) {  // <= 2 strides tried
    if ((p.n + k - 1) / k > max_length || 2 * k > D::kBandwidth) continue;
    bool fits = true;
    for (int off = 1; off <= D::kBandwidth; ++off) {  // <= Bw band columns
      if (off % k == 0 && off <= 2 * k) continue;     // a coupling the chains may have
      for (int i = off; i < p.n; ++i) fits = fits & (p.h_band[i][off] == S(0));  // < N
    }
    if (!fits) continue;
    for (int i = 0; i < p.n; ++i) seen[i] = 0;  // < N
    for (int r = 0; r < p.m && fits; ++r) {  // < M rows
      const int j = p.a_nnz[r] == 2 ? p.a_col[r][0] : -1;
      const S v = p.a_val[r][1];
      fits = j >= 0 && j + k < p.n && p.a_col[r][1] == j + k && v > S(0) && v < inf && p.a_val[r][0] == -v &&
             seen[j] == 0;
      if (fits) seen[j] = 1;
    }
    if (fits) return k;
  }
  return 0;
}

// One chain: positions q = 0..n-1 are the problem's variables first + q K.
// Its data is copied once per solve (each entry is read many times: a
// strided read costs an address computation each): g, lb and ub into
// storage the caller lends (solve_chain: rows of the workspace, which hold
// nothing during a chain solve), H's three diagonals here, with kPad zeros
// either side, so that (Hx)_q (hx()) needs no test at the chain's ends
// (with x padded the same way).
template <class D, int kMaxLength>
struct ChainData {
  using S = typename D::Scalar;
  static constexpr int kPad = 2;
  static constexpr std::size_t kLz = static_cast<std::size_t>(kMaxLength);
  static constexpr std::size_t kPadded = kLz + 2 * kPad;
  int n = 0;
  int first = 0;
  int stride = 1;
  S h0_[kPadded], h1_[kPadded], h2_[kPadded];  // [q + kPad]: H(q, q), H(q + 1, q), H(q + 2, q); 0 off the chain
  const S* g = nullptr;   // [q]: g, lb, ub of position q, in the lent storage
  const S* lb = nullptr;
  const S* ub = nullptr;
  S link_lo[kLz], link_hi[kLz];  // x_{q+1} - x_q in [lo, hi]; -inf / +inf: no link row
  std::int16_t link_row[kLz];    // the row behind link q, or -1
  bool linked = false;           // some link has a row

  int var(int q) const { return first + q * stride; }
  // Diagonals indexed by position, valid for q in [-kPad, n + kPad).
  const S* h0() const { return h0_ + kPad; }
  const S* h1() const { return h1_ + kPad; }
  const S* h2() const { return h2_ + kPad; }

  // (H x)_q along the chain (pentadiagonal); x padded like the diagonals
  // (x[-2], x[-1], x[n], x[n+1] are 0), so no test at the chain's ends.
  S hx(const S* x, int q) const {
    const S* d0 = h0();
    const S* d1 = h1();
    const S* d2 = h2();
    return d2[q - 2] * x[q - 2] + d1[q - 1] * x[q - 1] + d0[q] * x[q] + d1[q] * x[q + 1] + d2[q] * x[q + 2];
  }
};

// Chain `c` of a problem in chain form with stride `k` (find_stride: the band
// holds offset 2k), its g, lb and ub copied into g_out, lb_out, ub_out (at
// least kMaxLength each). The off-diagonals are read only where the chain
// has them (h1 below n - 1, h2 below n - 2).
// Returns whether the chain's entries of H are finite.
template <class D, int kMaxLength>
bool gather(const QpProblem<D>& p, int k, int c, ChainData<D, kMaxLength>& ch, typename D::Scalar* g_out,
            typename D::Scalar* lb_out, typename D::Scalar* ub_out) {
  using S = typename D::Scalar;
  const S inf = std::numeric_limits<S>::infinity();
  ch.first = c;
  ch.stride = k;
  ch.n = (p.n - c + k - 1) / k;
  ch.linked = false;
  ch.g = g_out;
  ch.lb = lb_out;
  ch.ub = ub_out;
  const int n = ch.n < kMaxLength ? ch.n : kMaxLength;
  S* h0 = ch.h0_ + ChainData<D, kMaxLength>::kPad;
  S* h1 = ch.h1_ + ChainData<D, kMaxLength>::kPad;
  S* h2 = ch.h2_ + ChainData<D, kMaxLength>::kPad;
  // Read: h0 to h2 at -2, -1 (zeros) and below n; h1 at n - 1 and h2 at n - 2, n - 1 are zeros.
  h0[-2] = h0[-1] = h1[-2] = h1[-1] = h2[-2] = h2[-1] = S(0);
  S zero_sum = S(0);  // v * 0 is 0 for a finite v, NaN otherwise
  for (int q = 0; q < n; ++q) {  // < kMaxLength
    const int j = c + q * k;
    g_out[q] = p.g[j];
    lb_out[q] = p.lb[j];
    ub_out[q] = p.ub[j];
    h0[q] = p.h_band[j][0];
    h1[q] = q + 1 < n ? p.h_band[j + k][k] : S(0);
    h2[q] = q + 2 < n ? p.h_band[j + 2 * k][2 * k] : S(0);
    zero_sum += (h0[q] + h1[q] + h2[q]) * S(0);
    ch.link_row[q] = -1;
    ch.link_lo[q] = -inf;
    ch.link_hi[q] = inf;
  }
  for (int r = 0; r < p.m; ++r) {  // < M: each row links p.a_col[r][0] to the next on its chain
    const int j = p.a_col[r][0];
    if (chain_of(j, k) != c) continue;
    const int q = position_of(j, k);
    ch.link_row[q] = static_cast<std::int16_t>(r);
    ch.linked = true;
    ch.link_lo[q] = p.lba[r] / p.a_val[r][1];
    ch.link_hi[q] = p.uba[r] / p.a_val[r][1];
  }
  return zero_sum == S(0);
}

}  // namespace itp::qp::chain
