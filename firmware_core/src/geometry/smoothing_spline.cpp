#include "itp/geometry/smoothing_spline.hpp"

#include "itp/configurations.hpp"
#include "itp/core/assert.hpp"

namespace itp::geometry {
namespace {

// Entry Q(r, k) of the second-difference matrix for interior knot k
// (1 <= k <= n-2): non-zero only for r = k-1, k, k+1.
Scalar q_entry(std::span<const Scalar> t, int r, int k) {
  const Scalar h_prev = t[static_cast<std::size_t>(k)] - t[static_cast<std::size_t>(k - 1)];
  const Scalar h_next = t[static_cast<std::size_t>(k + 1)] - t[static_cast<std::size_t>(k)];
  if (r == k - 1) {
    return Scalar(1) / h_prev;
  }
  if (r == k) {
    return -Scalar(1) / h_prev - Scalar(1) / h_next;
  }
  if (r == k + 1) {
    return Scalar(1) / h_next;
  }
  return Scalar(0);
}

}  // namespace

template <class Cfg>
bool fit_smoothing_spline(std::span<const Scalar> t, std::span<const Scalar> w,
                          std::span<const Scalar> y, Scalar lambda,
                          BasicSmoothingSplineWorkspace<Cfg>& ws, std::span<Scalar> g,
                          std::span<Scalar> gamma) {
  const int n = static_cast<int>(t.size());
  ITP_EXPECTS(n >= 3 && n <= Cfg::kMaxReferenceKnots);
  ITP_EXPECTS(w.size() == t.size() && y.size() == t.size());
  ITP_EXPECTS(g.size() == t.size() && gamma.size() == t.size());
  const auto at = [](std::span<const Scalar> v, int i) { return v[static_cast<std::size_t>(i)]; };
  const int m = n - 2;  // unknowns gamma_1 .. gamma_{n-2}, stored at j = k - 1

  // Assemble A = R + lambda Q^T W^-1 Q (bands 0, 1, 2) and Q^T y.
  for (int j = 0; j < Cfg::kMaxReferenceKnots && j < m; ++j) {
    const int k = j + 1;
    const Scalar h_prev = at(t, k) - at(t, k - 1);
    const Scalar h_next = at(t, k + 1) - at(t, k);
    Scalar diag = (h_prev + h_next) / Scalar(3);
    Scalar off1 = (j + 1 < m) ? h_next / Scalar(6) : Scalar(0);
    Scalar off2 = Scalar(0);
    // Rows r = k-1..k+1 of column k meet column k (diag), k+1 and k+2.
    for (int r = k - 1; r <= k + 1; ++r) {  // 3 rows
      const Scalar qk = q_entry(t, r, k) / at(w, r);
      diag += lambda * qk * q_entry(t, r, k);
      if (j + 1 < m) {
        off1 += lambda * qk * q_entry(t, r, k + 1);
      }
      if (j + 2 < m) {
        off2 += lambda * qk * q_entry(t, r, k + 2);
      }
    }
    ws.d[j] = diag;
    ws.a1[j] = off1;
    ws.a2[j] = off2;
    ws.rhs[j] = (at(y, k + 1) - at(y, k)) / h_next - (at(y, k) - at(y, k - 1)) / h_prev;
  }

  // Banded LDL^T in place: d <- D, l1/l2 <- L.
  for (int i = 0; i < Cfg::kMaxReferenceKnots && i < m; ++i) {
    ws.l2[i] = Scalar(0);
    ws.l1[i] = Scalar(0);
    Scalar di = ws.d[i];
    if (i >= 2) {
      ws.l2[i] = ws.a2[i - 2] / ws.d[i - 2];
      di -= ws.l2[i] * ws.l2[i] * ws.d[i - 2];
    }
    if (i >= 1) {
      const Scalar back = (i >= 2) ? ws.l2[i] * ws.l1[i - 1] * ws.d[i - 2] : Scalar(0);
      ws.l1[i] = (ws.a1[i - 1] - back) / ws.d[i - 1];
      di -= ws.l1[i] * ws.l1[i] * ws.d[i - 1];
    }
    if (!(di > Scalar(0))) {
      return false;
    }
    ws.d[i] = di;
  }
  // Solve L z = b, D u = z, L^T x = u (in rhs).
  for (int i = 0; i < Cfg::kMaxReferenceKnots && i < m; ++i) {
    if (i >= 1) ws.rhs[i] -= ws.l1[i] * ws.rhs[i - 1];
    if (i >= 2) ws.rhs[i] -= ws.l2[i] * ws.rhs[i - 2];
  }
  for (int i = 0; i < Cfg::kMaxReferenceKnots && i < m; ++i) {
    ws.rhs[i] /= ws.d[i];
  }
  for (int c = 0; c < Cfg::kMaxReferenceKnots && c < m; ++c) {
    const int i = m - 1 - c;
    if (i + 1 < m) ws.rhs[i] -= ws.l1[i + 1] * ws.rhs[i + 1];
    if (i + 2 < m) ws.rhs[i] -= ws.l2[i + 2] * ws.rhs[i + 2];
  }

  // gamma (natural ends) and g = y - lambda W^-1 Q gamma.
  for (int r = 0; r < Cfg::kMaxReferenceKnots && r < n; ++r) {
    gamma[static_cast<std::size_t>(r)] =
        (r == 0 || r == n - 1) ? Scalar(0) : ws.rhs[r - 1];
  }
  for (int r = 0; r < Cfg::kMaxReferenceKnots && r < n; ++r) {
    Scalar q_gamma = Scalar(0);
    for (int k = r - 1; k <= r + 1; ++k) {  // 3 columns touch row r
      if (k >= 1 && k <= n - 2) {
        q_gamma += q_entry(t, r, k) * gamma[static_cast<std::size_t>(k)];
      }
    }
    g[static_cast<std::size_t>(r)] = at(y, r) - lambda * q_gamma / at(w, r);
  }
  return true;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                               \
  template bool fit_smoothing_spline<C>(                                                 \
      std::span<const Scalar>, std::span<const Scalar>, std::span<const Scalar>, Scalar, \
      BasicSmoothingSplineWorkspace<C>&, std::span<Scalar>, std::span<Scalar>);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::geometry
