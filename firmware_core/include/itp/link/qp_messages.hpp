#pragma once
// QpSolve request and reply (docs/protocol.md): the host sends a QP in the
// solver's own sparse form, the firmware solves it cold on the target and
// returns status, iterations, objective, the solve time in ticks and x. Used
// to check that the target's arithmetic agrees with the host's.
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/link/byte_codec.hpp"
#include "itp/qp/problem.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::link {

// The reply for QPs of shape D (at most D::kMaxVariables values of x).
template <class D>
struct QpSolveReply {
  qp::QpStatus status = qp::QpStatus::kInvalidInput;
  std::uint16_t iterations = 0;
  std::uint16_t n = 0;
  double objective = 0;
  std::uint64_t ticks = 0;  // solve time on the target's counter
  double x[D::kMaxVariables] = {};
};

// Largest request and reply bodies for QPs of shape D [bytes] (layouts above).
template <class D>
inline constexpr std::size_t kMaxQpRequestBytes =
    5 + 8 * static_cast<std::size_t>(D::kMaxVariables) * (D::kBandwidth + 1) + 24 * D::kMaxVariables +
    static_cast<std::size_t>(D::kMaxRows) * (1 + 10 * D::kMaxRowNonzeros + 16);
template <class D>
inline constexpr std::size_t kMaxQpReplyBytes = 21 + 8 * static_cast<std::size_t>(D::kMaxVariables);

// Request body. Returns the size written, 0 if `out` is too small.
template <class D>
std::size_t encode_qp_request(const qp::QpProblem<D>& p, std::span<std::uint8_t> out) {
  ByteWriter w(out);
  w.u16(static_cast<std::uint16_t>(p.n));
  w.u16(static_cast<std::uint16_t>(p.m));
  w.u8(static_cast<std::uint8_t>(D::kBandwidth));
  for (int i = 0; i < p.n; ++i) {                   // n x (bw + 1) band entries
    for (int k = 0; k <= D::kBandwidth; ++k) {
      w.f64(k <= i ? static_cast<double>(p.h_band[i][k]) : 0.0);
    }
  }
  for (int i = 0; i < p.n; ++i) {  // n
    w.f64(static_cast<double>(p.g[i]));
    w.f64(static_cast<double>(p.lb[i]));
    w.f64(static_cast<double>(p.ub[i]));
  }
  for (int r = 0; r < p.m; ++r) {  // m rows
    w.u8(static_cast<std::uint8_t>(p.a_nnz[r]));
    for (int k = 0; k < p.a_nnz[r]; ++k) {  // <= NnzRow
      w.u16(static_cast<std::uint16_t>(p.a_col[r][k]));
      w.f64(static_cast<double>(p.a_val[r][k]));
    }
    w.f64(static_cast<double>(p.lba[r]));
    w.f64(static_cast<double>(p.uba[r]));
  }
  return w.ok() ? w.size() : 0;
}

// Decodes into `p` (capacity D). False on any size beyond capacity, bad
// column order or a body of the wrong length.
template <class D>
bool decode_qp_request(std::span<const std::uint8_t> in, qp::QpProblem<D>& p) {
  using S = typename D::Scalar;
  ByteReader r(in);
  const int n = r.u16();
  const int m = r.u16();
  const int bw = r.u8();
  if (!r.ok() || bw > D::kBandwidth || !p.reset(n, m)) {
    return false;
  }
  for (int i = 0; i < n; ++i) {       // n <= kMaxVariables
    for (int k = 0; k <= bw; ++k) {   // bw <= kBandwidth
      const double v = r.f64();
      if (k <= i) {
        p.h_band[i][k] = static_cast<S>(v);
      }
    }
  }
  for (int i = 0; i < n; ++i) {  // n
    p.g[i] = static_cast<S>(r.f64());
    p.lb[i] = static_cast<S>(r.f64());
    p.ub[i] = static_cast<S>(r.f64());
  }
  for (int row = 0; row < m; ++row) {  // m <= kMaxRows
    const int nnz = r.u8();
    if (nnz > D::kMaxRowNonzeros) {
      return false;
    }
    for (int k = 0; k < nnz; ++k) {  // <= kMaxRowNonzeros
      const int col = r.u16();
      const double v = r.f64();
      if (!r.ok() || !p.push_row_entry(row, col, static_cast<S>(v))) {
        return false;
      }
    }
    p.lba[row] = static_cast<S>(r.f64());
    p.uba[row] = static_cast<S>(r.f64());
  }
  return r.done();
}

template <class D>
std::size_t encode(const QpSolveReply<D>& msg, std::span<std::uint8_t> out) {
  ByteWriter w(out);
  w.u8(static_cast<std::uint8_t>(msg.status));
  w.u16(msg.iterations);
  w.u16(msg.n);
  w.f64(msg.objective);
  w.u64(msg.ticks);
  for (int i = 0; i < msg.n && i < D::kMaxVariables; ++i) {  // n <= kMaxVariables
    w.f64(msg.x[i]);
  }
  return w.ok() && msg.n <= D::kMaxVariables ? w.size() : 0;
}

template <class D>
bool decode(std::span<const std::uint8_t> in, QpSolveReply<D>& msg) {
  ByteReader r(in);
  msg.status = static_cast<qp::QpStatus>(r.u8());
  msg.iterations = r.u16();
  msg.n = r.u16();
  msg.objective = r.f64();
  msg.ticks = r.u64();
  if (msg.n > D::kMaxVariables) {
    return false;
  }
  for (int i = 0; i < msg.n; ++i) {  // n <= kMaxVariables
    msg.x[i] = r.f64();
  }
  return r.done();
}

}  // namespace itp::link
