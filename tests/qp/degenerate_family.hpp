#pragma once
// Degenerate, badly scaled QPs whose optimum is known EXACTLY by construction
// (issue 15, item 3): every number is exact in double, so x* is the optimum of
// the very data the solver sees, not of a rounded neighbour.
//
// Construction (all integers before scaling, magnitudes far below 2^53):
//   x*      integers in [-4, 4]
//   H       banded integer matrix, strictly diagonally dominant (H > 0), so x* is
//           the unique optimum
//   a_r     small integers on a window of consecutive columns (fits the band)
//   y0_r    integer multipliers with the sign of the active side (0: inactive,
//           weakly active, or a redundant copy)
//   g       = -(H x* + sum_r a_r y0_r + y_bounds)   (exact integer arithmetic)
// Row r is then scaled by s_r = c_r 2^k_r with odd c_r in {1,3,..,15} and
// k_r in [-17, 16] (|s_r| from 7.6e-6 to 9.8e5): a_r -> s_r a_r, its bounds ->
// s_r b_r, and its multiplier y0_r = c_r q_r -> q_r 2^-k_r, all exact, so the
// KKT conditions hold exactly for the scaled data too.
// Degeneracy: weakly active rows and bounds (active with multiplier 0),
// equalities, exact duplicates of active rows under a different scale, rows
// that are sums of two active rows (dependent, weakly active), and sometimes
// more active constraints than variables; optionally rows that are such sums
// plus 2^-20 in one entry (independent, but barely) and variables scaled by
// powers of two.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "itp/qp/qp.hpp"

namespace qp_test {

struct FamilyOptions {
  int n = 63;
  int m = 300;
  int bandwidth = 5;        // of H, <= D::kBandwidth
  int row_width = 6;        // consecutive columns a row may touch, <= D::kMaxRowNonzeros
  double p_active = 0.35;   // of the rows (strongly or weakly) active at x*
  double p_weak = 0.3;      // of the active constraints: multiplier 0
  double p_equality = 0.1;  // of the active rows
  double p_copy = 0.15;     // of the rows: a rescaled copy of an earlier active row
  double p_sum = 0.1;       // of the rows: the sum of two earlier active rows
  double p_bound_active = 0.3;
  double p_near = 0.0;      // of the rows: a sum of two active rows plus 2^-near_exponent e_j
  int near_exponent = 20;   //   (nearly dependent, weakly active)
  int min_exponent = -17;   // row scales c 2^k, k in [min_exponent, max_exponent]
  int max_exponent = 16;
  int column_exponent = 0;  // variables scaled by 2^e, e in [-column_exponent, column_exponent]
};

struct FamilyOptimum {
  std::vector<double> x;      // the optimum x*
  double objective = 0.0;     // 1/2 x*'Hx* + g'x*, exact up to one rounding
  int active = 0;             // constraints active at x* (bounds + rows)
};

template <class D>
FamilyOptimum build_family_member(itp::qp::QpProblem<D>& p, const FamilyOptions& o, std::mt19937& rng) {
  const double inf = std::numeric_limits<double>::infinity();
  std::uniform_int_distribution<int> small(-4, 4);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const int n = o.n, m = o.m;
  p.reset(n, m);
  FamilyOptimum out;
  out.x.resize(static_cast<std::size_t>(n));
  for (auto& v : out.x) v = small(rng);
  auto X = [&](int j) { return out.x[static_cast<std::size_t>(j)]; };
  // H: integer band, strictly diagonally dominant.
  std::vector<double> hrow_sum(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    for (int j = i - o.bandwidth < 0 ? 0 : i - o.bandwidth; j < i; ++j) {
      const double v = small(rng);
      p.set_hessian(i, j, v);
      hrow_sum[static_cast<std::size_t>(i)] += std::abs(v);
      hrow_sum[static_cast<std::size_t>(j)] += std::abs(v);
    }
  }
  for (int i = 0; i < n; ++i) p.set_hessian(i, i, hrow_sum[static_cast<std::size_t>(i)] + 1.0 + (i % 4));
  // grad = H x* + A'y + y_b, accumulated exactly (integers).
  std::vector<double> grad(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) grad[static_cast<std::size_t>(i)] += p.hessian(i, j) * X(j);
  }
  // Unscaled active rows so far (for copies and sums): columns, values, value a'x*, side.
  struct Active {
    std::vector<int> col;
    std::vector<double> val;
    double ax;
    int side;  // -1 lower, +1 upper, 0 equality
  };
  std::vector<Active> actives;
  std::uniform_int_distribution<int> odd(0, 7);
  std::uniform_int_distribution<int> expo(o.min_exponent, o.max_exponent);
  for (int r = 0; r < m; ++r) {
    Active row;
    const double pick = uni(rng);
    bool weak = uni(rng) < o.p_weak;
    if (pick < o.p_copy && !actives.empty()) {
      row = actives[static_cast<std::size_t>(uni(rng) * static_cast<double>(actives.size()))];
      weak = weak || uni(rng) < 0.5;
    } else if (pick < o.p_copy + o.p_sum + o.p_near && actives.size() >= 2) {
      const bool near = pick >= o.p_copy + o.p_sum;
      // the sum of two active rows with the same side (a dependent row)
      const Active& a1 = actives[static_cast<std::size_t>(uni(rng) * static_cast<double>(actives.size()))];
      const Active& a2 = actives[static_cast<std::size_t>(uni(rng) * static_cast<double>(actives.size()))];
      std::vector<double> dense(static_cast<std::size_t>(n), 0.0);
      for (std::size_t k = 0; k < a1.col.size(); ++k) dense[static_cast<std::size_t>(a1.col[k])] += a1.val[k];
      for (std::size_t k = 0; k < a2.col.size(); ++k) dense[static_cast<std::size_t>(a2.col[k])] += a2.val[k];
      int width = 0;
      for (int j = 0; j < n; ++j) {
        if (dense[static_cast<std::size_t>(j)] != 0.0) ++width;
      }
      if (width > D::kMaxRowNonzeros || width == 0 || a1.side != a2.side || a1.side == 0) {
        row.col.clear();
      } else {
        for (int j = 0; j < n; ++j) {
          if (dense[static_cast<std::size_t>(j)] != 0.0) {
            row.col.push_back(j);
            row.val.push_back(dense[static_cast<std::size_t>(j)]);
          }
        }
        row.ax = a1.ax + a2.ax;
        row.side = a1.side;
        weak = true;  // implied by the two: its multiplier stays 0
        if (near) {
          // perturb one entry by 2^-near_exponent: independent, but barely
          const double delta = std::ldexp(1.0, -o.near_exponent);
          row.val[0] += delta;
          row.ax += delta * X(row.col[0]);
        }
      }
    }
    const bool derived = !row.col.empty();
    if (!derived) {
      const int width = 1 + static_cast<int>(uni(rng) * o.row_width);
      const int start = static_cast<int>(uni(rng) * (n - width + 1));
      row.ax = 0.0;
      for (int j = start; j < start + width; ++j) {
        int v = small(rng);
        if (v == 0) v = 1;
        row.col.push_back(j);
        row.val.push_back(v);
        row.ax += v * X(j);
      }
    }
    const bool active = derived || uni(rng) < o.p_active;
    if (active && !derived) {
      row.side = uni(rng) < o.p_equality ? 0 : (uni(rng) < 0.5 ? -1 : 1);
    }
    const int c = 2 * odd(rng) + 1;
    const int k = expo(rng);
    const double s = std::ldexp(static_cast<double>(c), k);
    for (std::size_t q = 0; q < row.col.size(); ++q) p.push_row_entry(r, row.col[q], s * row.val[q]);
    double y0 = 0.0;  // unscaled multiplier, a multiple of c
    if (active) {
      const double lo_gap = 1 + static_cast<int>(uni(rng) * 5);
      if (row.side == 0) {
        p.lba[r] = p.uba[r] = s * row.ax;
        if (!weak) y0 = c * static_cast<double>(small(rng));
      } else if (row.side > 0) {
        p.uba[r] = s * row.ax;
        p.lba[r] = uni(rng) < 0.3 ? -inf : s * (row.ax - lo_gap);
        if (!weak) y0 = c * static_cast<double>(1 + static_cast<int>(uni(rng) * 4));
      } else {
        p.lba[r] = s * row.ax;
        p.uba[r] = uni(rng) < 0.3 ? inf : s * (row.ax + lo_gap);
        if (!weak) y0 = -c * static_cast<double>(1 + static_cast<int>(uni(rng) * 4));
      }
      if (!derived) actives.push_back(row);
      ++out.active;
    } else {
      p.lba[r] = uni(rng) < 0.2 ? -inf : s * (row.ax - (1 + static_cast<int>(uni(rng) * 5)));
      p.uba[r] = uni(rng) < 0.2 ? inf : s * (row.ax + (1 + static_cast<int>(uni(rng) * 5)));
    }
    // a_r y_r = (s a) (y0 / s): exact, as y0 / s = (y0 / c) 2^-k.
    for (std::size_t q = 0; q < row.col.size(); ++q) grad[static_cast<std::size_t>(row.col[q])] += row.val[q] * y0;
  }
  for (int j = 0; j < n; ++j) {
    const auto u = static_cast<std::size_t>(j);
    if (uni(rng) < o.p_bound_active) {
      const bool upper = uni(rng) < 0.5;
      const double yb = uni(rng) < o.p_weak ? 0.0 : (upper ? 1.0 : -1.0) * (1 + static_cast<int>(uni(rng) * 4));
      if (upper) {
        p.ub[j] = X(j);
        p.lb[j] = uni(rng) < 0.3 ? -inf : X(j) - (1 + static_cast<int>(uni(rng) * 3));
      } else {
        p.lb[j] = X(j);
        p.ub[j] = uni(rng) < 0.3 ? inf : X(j) + (1 + static_cast<int>(uni(rng) * 3));
      }
      grad[u] += yb;
      ++out.active;
    } else {
      p.lb[j] = uni(rng) < 0.3 ? -inf : X(j) - (1 + static_cast<int>(uni(rng) * 3));
      p.ub[j] = uni(rng) < 0.3 ? inf : X(j) + (1 + static_cast<int>(uni(rng) * 3));
    }
  }
  for (int j = 0; j < n; ++j) p.g[j] = -grad[static_cast<std::size_t>(j)];
  double obj = 0.0;
  for (int i = 0; i < n; ++i) {
    double hx = 0.0;
    for (int j = 0; j < n; ++j) hx += p.hessian(i, j) * X(j);
    obj += X(i) * (0.5 * hx + p.g[i]);
  }
  out.objective = obj;
  // Variable scaling x = D z, D = diag(2^e_j): H -> DHD, A -> AD, g -> Dg,
  // bounds and x* -> D^-1 (exact; the objective is unchanged).
  if (o.column_exponent > 0) {
    std::uniform_int_distribution<int> ce(-o.column_exponent, o.column_exponent);
    std::vector<double> d(static_cast<std::size_t>(n));
    for (auto& v : d) v = std::ldexp(1.0, ce(rng));
    auto Dj = [&](int j) { return d[static_cast<std::size_t>(j)]; };
    for (int i = 0; i < n; ++i) {
      for (int j = i - o.bandwidth < 0 ? 0 : i - o.bandwidth; j <= i; ++j) {
        p.set_hessian(i, j, p.hessian(i, j) * Dj(i) * Dj(j));
      }
      p.g[i] *= Dj(i);
      p.lb[i] /= Dj(i);
      p.ub[i] /= Dj(i);
      out.x[static_cast<std::size_t>(i)] /= Dj(i);
    }
    for (int r = 0; r < m; ++r) {
      for (int q = 0; q < p.a_nnz[r]; ++q) p.a_val[r][q] *= Dj(p.a_col[r][q]);
    }
  }
  return out;
}

}  // namespace qp_test
