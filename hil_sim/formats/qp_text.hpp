#pragma once
// Reader and writer of `qp-text/1` (docs/formats.md, FORMATS.md): a QP
//   min 1/2 x'Hx + g'x  s.t.  lbA <= Ax <= ubA,  lb <= x <= ub
// as whitespace-separated text with dense row-major H and A, plus the
// conversion to and from the solver's banded/row-sparse itp::qp::QpProblem.
#include <cmath>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "itp/qp/problem.hpp"

namespace hil::formats {

// The file's content, dense, in double.
struct QpText {
  int n = 0;
  int m = 0;
  std::vector<double> H;    // n x n, row-major
  std::vector<double> g;    // n
  std::vector<double> A;    // m x n, row-major
  std::vector<double> lbA;  // m
  std::vector<double> ubA;  // m
  std::vector<double> lb;   // n
  std::vector<double> ub;   // n
  std::optional<std::vector<double>> x_ref;  // optional reference solution
  std::optional<double> obj_ref;             // optional reference objective
};

// The reader's limits, checked on the header before anything is allocated:
// a file beyond them is refused with a message (a qp-text/1 file at the
// limit holds 2^25 numbers, about 0.5 GB of text).
inline constexpr int kMaxTextVariables = 4096;
inline constexpr int kMaxTextRows = 65536;
inline constexpr long long kMaxTextEntries = 1LL << 25;  // n (n + m)

// Parses qp-text/1. On failure returns false and says why (with the section).
// Memory grows with the numbers actually read, never with what the header
// claims; no exception escapes (an exhausted heap is an error message).
bool read_qp_text(std::istream& in, QpText& qp, std::string& error);
bool read_qp_text_file(const std::string& path, QpText& qp, std::string& error);
// Writes qp-text/1 with round-trip precision (%.17g), `inf` / `-inf`.
void write_qp_text(std::ostream& out, const QpText& qp);
bool write_qp_text_file(const std::string& path, const QpText& qp, std::string& error);

// Dense file -> solver form. Fails with a clear message when n, m, the
// half-bandwidth of H, a row's nonzero count exceed the capacities of D, or H
// is not symmetric.
template <class D>
bool to_problem(const QpText& qp, itp::qp::QpProblem<D>& p, std::string& error) {
  using S = typename D::Scalar;
  if (qp.n < 1 || qp.n > D::kMaxVariables || qp.m < 0 || qp.m > D::kMaxRows) {
    error = "size n=" + std::to_string(qp.n) + " m=" + std::to_string(qp.m) +
            " beyond capacity n<=" + std::to_string(D::kMaxVariables) +
            " m<=" + std::to_string(D::kMaxRows);
    return false;
  }
  const auto n = static_cast<std::size_t>(qp.n);
  if (!p.reset(qp.n, qp.m)) {
    error = "size beyond capacity";
    return false;
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j <= i; ++j) {
      const double hij = qp.H[i * n + j];
      if (hij != qp.H[j * n + i]) {
        error = "H is not symmetric at (" + std::to_string(i) + "," + std::to_string(j) + ")";
        return false;
      }
      if (hij == 0.0) continue;
      if (i - j > static_cast<std::size_t>(D::kBandwidth)) {
        error = "H is not banded within capacity: H(" + std::to_string(i) + "," +
                std::to_string(j) + ") != 0 at distance " + std::to_string(i - j) +
                " > half-bandwidth " + std::to_string(D::kBandwidth);
        return false;
      }
      p.set_hessian(static_cast<int>(i), static_cast<int>(j), static_cast<S>(hij));
    }
    p.g[i] = static_cast<S>(qp.g[i]);
    p.lb[i] = static_cast<S>(qp.lb[i]);
    p.ub[i] = static_cast<S>(qp.ub[i]);
  }
  for (int r = 0; r < qp.m; ++r) {
    const auto rr = static_cast<std::size_t>(r);
    for (std::size_t j = 0; j < n; ++j) {
      const double a = qp.A[rr * n + j];
      if (a == 0.0) continue;
      if (!p.push_row_entry(r, static_cast<int>(j), static_cast<S>(a))) {
        error = "row " + std::to_string(r) + " of A has more than " +
                std::to_string(D::kMaxRowNonzeros) + " nonzeros";
        return false;
      }
    }
    p.lba[r] = static_cast<S>(qp.lbA[rr]);
    p.uba[r] = static_cast<S>(qp.ubA[rr]);
  }
  return true;
}

// Solver form -> dense file content (used by the planner to dump its QPs).
template <class D>
QpText from_problem(const itp::qp::QpProblem<D>& p) {
  QpText qp;
  qp.n = p.n;
  qp.m = p.m;
  const auto n = static_cast<std::size_t>(p.n);
  const auto m = static_cast<std::size_t>(p.m);
  qp.H.assign(n * n, 0.0);
  qp.A.assign(m * n, 0.0);
  for (int i = 0; i < p.n; ++i) {
    for (int j = 0; j < p.n; ++j) {
      qp.H[static_cast<std::size_t>(i) * n + static_cast<std::size_t>(j)] =
          static_cast<double>(p.hessian(i, j));
    }
    qp.g.push_back(static_cast<double>(p.g[i]));
    qp.lb.push_back(static_cast<double>(p.lb[i]));
    qp.ub.push_back(static_cast<double>(p.ub[i]));
  }
  for (int r = 0; r < p.m; ++r) {
    for (int k = 0; k < p.a_nnz[r]; ++k) {
      qp.A[static_cast<std::size_t>(r) * n + static_cast<std::size_t>(p.a_col[r][k])] =
          static_cast<double>(p.a_val[r][k]);
    }
    qp.lbA.push_back(static_cast<double>(p.lba[r]));
    qp.ubA.push_back(static_cast<double>(p.uba[r]));
  }
  return qp;
}

}  // namespace hil::formats
