#pragma once
// Builders of QPs whose optimum is known by construction (choose x*, the
// active set and multipliers, derive g and the bounds so that KKT holds),
// plus small helpers shared by the QP tests.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <doctest/doctest.h>

#include "heap_guard.hpp"
#include "itp/qp/qp.hpp"

namespace qp_test {

struct Constructed;
template <class D>
void finish_gradient(itp::qp::QpProblem<D>& p, const Constructed& c);

template <typename S>
constexpr S inf() { return std::numeric_limits<S>::infinity(); }

// One QP with its workspace, result and settings (large: allocate with
// std::make_unique); solve() is a cold solve that must not touch the heap.
template <class D>
struct Instance {
  itp::qp::QpProblem<D> problem;
  itp::qp::QpWorkspace<D> ws;
  itp::qp::QpResult<D> result;
  itp::qp::QpSettings<typename D::Scalar> settings;
  itp::qp::QpStatus solve() {
    test_support::HeapGuard guard;
    return itp::qp::solve_cold(problem, ws, settings, result);
  }
};

struct BuildOptions {
  int n = 10;
  int m = 10;
  int bandwidth = 2;          // <= D::kBandwidth
  int max_row_nnz = 3;        // <= D::kMaxRowNonzeros
  bool clustered_rows = true; // row columns within a window (banded-looking)
  double p_row_active = 0.3;
  double p_bound_active = 0.2;
  double p_equality = 0.05;   // of the active constraints
  double p_weak = 0.0;        // active with zero multiplier (degenerate)
  double p_infinite = 0.2;    // a non-active side is infinite
  bool well_conditioned = true;
};

// The constructed optimum, in double regardless of the problem's scalar.
struct Constructed {
  std::vector<double> x, y_bounds, y_rows;
};

template <class D>
Constructed build_random(itp::qp::QpProblem<D>& p, const BuildOptions& o, std::mt19937& rng) {
  using S = typename D::Scalar;
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const int n = o.n, m = o.m;
  REQUIRE(p.reset(n, m));
  Constructed c;
  c.x.resize(static_cast<std::size_t>(n));
  c.y_bounds.assign(static_cast<std::size_t>(n), 0.0);
  c.y_rows.assign(static_cast<std::size_t>(m), 0.0);
  for (auto& v : c.x) v = 2.0 * gauss(rng);

  // H: symmetric band, positive definite by diagonal dominance (or, with
  // well_conditioned = false, a band Gram matrix B B' plus a small shift).
  std::vector<double> h(static_cast<std::size_t>(n * n), 0.0);
  auto H = [&](int i, int j) -> double& { return h[static_cast<std::size_t>(i * n + j)]; };
  const int bw = std::min(o.bandwidth, n - 1);
  if (o.well_conditioned) {
    for (int i = 0; i < n; ++i) {
      for (int j = std::max(0, i - bw); j < i; ++j) {
        const double v = 2.0 * uni(rng) - 1.0;
        H(i, j) = v;
        H(j, i) = v;
      }
    }
    for (int i = 0; i < n; ++i) {
      double s = 0.0;
      for (int j = 0; j < n; ++j) {
        if (j != i) s += std::abs(H(i, j));
      }
      H(i, i) = s + 0.5 + 2.0 * uni(rng);
    }
  } else {
    // lower band B with half-bandwidth bw: B B' has half-bandwidth bw too
    // only when B is bidiagonal-like; use B with band bw/2 (rounded down).
    const int b = bw / 2;
    std::vector<double> B(static_cast<std::size_t>(n * n), 0.0);
    for (int i = 0; i < n; ++i) {
      for (int j = std::max(0, i - b); j <= i; ++j) {
        B[static_cast<std::size_t>(i * n + j)] = gauss(rng);
      }
    }
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        double s = 0.0;
        for (int k = 0; k < n; ++k) {
          s += B[static_cast<std::size_t>(i * n + k)] * B[static_cast<std::size_t>(j * n + k)];
        }
        H(i, j) = s + (i == j ? 1e-2 : 0.0);
      }
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = std::max(0, i - bw); j <= i; ++j) REQUIRE(p.set_hessian(i, j, static_cast<S>(H(i, j))));
  }
  // Store back the rounded values so the construction is exact in S.
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) H(i, j) = static_cast<double>(p.hessian(i, j));
  }
  // Round x* to S as well.
  for (auto& v : c.x) v = static_cast<double>(static_cast<S>(v));

  // Rows.
  for (int r = 0; r < m; ++r) {
    const int nnz = 1 + static_cast<int>(uni(rng) * std::min(o.max_row_nnz, n));
    const int k = std::min(nnz, std::min(o.max_row_nnz, n));
    std::vector<int> cols;
    if (o.clustered_rows) {
      const int width = std::min(n, std::max(k, o.bandwidth + 1));
      const int start = static_cast<int>(uni(rng) * (n - width + 1));
      std::vector<int> win;
      for (int j = start; j < start + width; ++j) win.push_back(j);
      std::shuffle(win.begin(), win.end(), rng);
      cols.assign(win.begin(), win.begin() + k);
    } else {
      std::vector<int> all(static_cast<std::size_t>(n));
      for (int j = 0; j < n; ++j) all[static_cast<std::size_t>(j)] = j;
      std::shuffle(all.begin(), all.end(), rng);
      cols.assign(all.begin(), all.begin() + k);
    }
    std::sort(cols.begin(), cols.end());
    for (int col : cols) {
      double v = gauss(rng);
      if (std::abs(v) < 0.1) v = v < 0 ? -0.5 : 0.5;
      REQUIRE(p.push_row_entry(r, col, static_cast<S>(v)));
    }
  }
  auto row_value = [&](int r) {
    double s = 0.0;
    for (int k = 0; k < p.a_nnz[r]; ++k) {
      s += static_cast<double>(p.a_val[r][k]) * c.x[static_cast<std::size_t>(p.a_col[r][k])];
    }
    return s;
  };
  // Sides: active (with multiplier sign), inactive with a margin.
  auto make_sides = [&](double value, double p_active, double& y, S& lo, S& hi) {
    if (uni(rng) < p_active) {
      const bool upper = uni(rng) < 0.5;
      const bool weak = uni(rng) < o.p_weak;
      const double mag = weak ? 0.0 : 0.1 + 2.0 * uni(rng);
      if (uni(rng) < o.p_equality) {
        y = (upper ? 1.0 : -1.0) * mag;
        lo = hi = static_cast<S>(value);
      } else if (upper) {
        y = mag;
        hi = static_cast<S>(value);
        lo = uni(rng) < o.p_infinite ? -inf<S>() : static_cast<S>(value - 0.1 - 3.0 * uni(rng));
      } else {
        y = -mag;
        lo = static_cast<S>(value);
        hi = uni(rng) < o.p_infinite ? inf<S>() : static_cast<S>(value + 0.1 + 3.0 * uni(rng));
      }
    } else {
      y = 0.0;
      lo = uni(rng) < o.p_infinite ? -inf<S>() : static_cast<S>(value - 0.05 - 2.0 * uni(rng));
      hi = uni(rng) < o.p_infinite ? inf<S>() : static_cast<S>(value + 0.05 + 2.0 * uni(rng));
    }
  };
  for (int r = 0; r < m; ++r) {
    make_sides(row_value(r), o.p_row_active, c.y_rows[static_cast<std::size_t>(r)], p.lba[r], p.uba[r]);
  }
  for (int j = 0; j < n; ++j) {
    make_sides(c.x[static_cast<std::size_t>(j)], o.p_bound_active, c.y_bounds[static_cast<std::size_t>(j)],
               p.lb[j], p.ub[j]);
  }
  finish_gradient(p, c);
  return c;
}

// Sets g = -(H x* + A'y_rows + y_bounds) so that stationarity holds at x*.
template <class D>
void finish_gradient(itp::qp::QpProblem<D>& p, const Constructed& c) {
  using S = typename D::Scalar;
  const int n = p.n;
  std::vector<double> grad(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      grad[static_cast<std::size_t>(i)] += static_cast<double>(p.hessian(i, j)) * c.x[static_cast<std::size_t>(j)];
    }
    grad[static_cast<std::size_t>(i)] += c.y_bounds[static_cast<std::size_t>(i)];
  }
  for (int r = 0; r < p.m; ++r) {
    for (int k = 0; k < p.a_nnz[r]; ++k) {
      grad[static_cast<std::size_t>(p.a_col[r][k])] +=
          static_cast<double>(p.a_val[r][k]) * c.y_rows[static_cast<std::size_t>(r)];
    }
  }
  for (int i = 0; i < n; ++i) p.g[i] = static_cast<S>(-grad[static_cast<std::size_t>(i)]);
}

// Rows 0..k-1 of an infeasible system (Farkas: y >= 0 with sum y_i a_i = 0 and
// sum y_i b_i < 0 makes {a_i'x <= b_i} empty), rows k..k+2 harmless boxes,
// and a random positive definite H and g; n variables, k + 3 rows.
// flip_first: row 0 written as the lower side of -a_0.
template <class D>
void build_farkas(itp::qp::QpProblem<D>& p, int n, int k, bool flip_first, std::mt19937& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  REQUIRE(p.reset(n, k + 3));
  for (int i = 0; i < n; ++i) {
    p.set_hessian(i, i, 1.0 + uni(rng));
    if (i > 0) p.set_hessian(i, i - 1, 0.3 * gauss(rng));
    p.g[i] = gauss(rng);
  }
  std::vector<double> sum(static_cast<std::size_t>(n), 0.0);
  double yb = 0.0;
  const double y_last = 0.5 + uni(rng);
  for (int r = 0; r < k - 1; ++r) {
    const double y = 0.5 + uni(rng);
    for (int j = 0; j < n; ++j) {
      const double a = gauss(rng);
      p.push_row_entry(r, j, a);
      sum[static_cast<std::size_t>(j)] += y * a;
    }
    const double b = gauss(rng);
    // alternate the representation: upper side, or the lower side of -a.
    p.uba[r] = b;
    yb += y * b;
  }
  for (int j = 0; j < n; ++j) p.push_row_entry(k - 1, j, -sum[static_cast<std::size_t>(j)] / y_last);
  // need y_last * b_last < -yb  ->  b_last = (-yb - margin) / y_last
  p.uba[k - 1] = (-yb - 0.5 - uni(rng)) / y_last;
  if (flip_first) {  // row 0 as a lower-side constraint on -a
    for (int q = 0; q < p.a_nnz[0]; ++q) p.a_val[0][q] = -p.a_val[0][q];
    p.lba[0] = -p.uba[0];
    p.uba[0] = qp_test::inf<double>();
  }
  // Three harmless box rows after the infeasible ones (size_t indices keep
  // GCC 12's -Warray-bounds from a false positive at -O3).
  for (std::size_t r = static_cast<std::size_t>(k); r < static_cast<std::size_t>(k) + 3; ++r) {
    p.push_row_entry(static_cast<int>(r), static_cast<int>(r) % n, 1.0);
    p.lba[r] = -100.0;
    p.uba[r] = 100.0;
  }
}

template <class D>
double max_abs_diff(const itp::qp::QpResult<D>& res, const std::vector<double>& x, int n) {
  double d = 0.0;
  for (int j = 0; j < n; ++j) {
    d = std::max(d, std::abs(static_cast<double>(res.x[j]) - x[static_cast<std::size_t>(j)]));
  }
  return d;
}

template <typename T>
double max_abs(const std::vector<T>& v) {
  double m = 0.0;
  for (const auto& e : v) m = std::max(m, std::abs(static_cast<double>(e)));
  return m;
}

}  // namespace qp_test
