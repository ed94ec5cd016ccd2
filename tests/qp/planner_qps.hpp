#pragma once
// QP instances shaped like the planner's (docs/qp.md, PLANNER.md): the path
// QP on quintic Hermite SL blocks, the speed QP on quintic ST blocks and the
// coarse decision QP. Shared by the tests and the benchmark; they need no
// test framework. Costs are integrated exactly (6-point Gauss-Legendre is
// exact for the degree-10 integrands of a quintic).
#include <algorithm>
#include <cmath>
#include <limits>

#include "itp/qp/problem.hpp"

namespace planner_qps {

// Quintic Hermite basis on t in [0, 1], coefficients of t^0..t^5, in the order
// (value, slope, curvature) at t = 0, then at t = 1.
inline constexpr double kHermite[6][6] = {
    {1, 0, 0, -10, 15, -6},        // value at 0
    {0, 1, 0, -6, 8, -3},          // 1st derivative at 0
    {0, 0, 0.5, -1.5, 1.5, -0.5},  // 2nd derivative at 0
    {0, 0, 0, 10, -15, 6},         // value at 1
    {0, 0, 0, -4, 7, -3},          // 1st derivative at 1
    {0, 0, 0, 0.5, -1, 0.5},       // 2nd derivative at 1
};

// d^k/dt^k of basis function a at t.
inline double basis_dt(int a, int k, double t) {
  double sum = 0.0;
  for (int p = k; p < 6; ++p) {
    double c = kHermite[a][p];
    for (int q = 0; q < k; ++q) c *= static_cast<double>(p - q);
    sum += c * std::pow(t, p - k);
  }
  return sum;
}

// d^k/ds^k of the block's shape function for knot variable a (0..5) on a
// block of length h: derivative variables carry h, h^2 scalings.
inline double shape(int a, int k, double t, double h) {
  static constexpr int kDerivOrder[6] = {0, 1, 2, 0, 1, 2};
  return basis_dt(a, k, t) * std::pow(h, kDerivOrder[a] - k);
}

inline constexpr double kGaussT[6] = {0.033765242898423975, 0.16939530676686776,
                                      0.38069040695840156,  0.6193095930415985,
                                      0.8306046932331322,   0.966234757101576};
inline constexpr double kGaussW[6] = {0.08566224618958517, 0.18038078652406933,
                                      0.23395696728634552, 0.23395696728634552,
                                      0.18038078652406933, 0.08566224618958517};

// Adds the exact cost of one block, sum_k w[k] int (d^k l/ds^k - ref_k)^2 ds,
// to H (times 2, for the 1/2 x'Hx form) and g; ref only for k = 0, 1.
template <class D>
void add_block_cost(itp::qp::QpProblem<D>& p, int first_var, double h, const double w[4],
                    double ref0, double ref1) {
  using S = typename D::Scalar;
  double hb[6][6] = {};
  double gb[6] = {};
  for (int q = 0; q < 6; ++q) {
    const double t = kGaussT[q];
    const double wq = kGaussW[q] * h;
    for (int a = 0; a < 6; ++a) {
      for (int k = 0; k < 4; ++k) {
        const double fa = shape(a, k, t, h);
        for (int b = 0; b < 6; ++b) hb[a][b] += 2.0 * wq * w[k] * fa * shape(b, k, t, h);
      }
      gb[a] += -2.0 * wq * (w[0] * ref0 * shape(a, 0, t, h) + w[1] * ref1 * shape(a, 1, t, h));
    }
  }
  for (int a = 0; a < 6; ++a) {
    for (int b = 0; b <= a; ++b) {
      const int i = first_var + a, j = first_var + b;
      p.set_hessian(i, j, p.hessian(i, j) + static_cast<S>(hb[a][b]));
    }
    p.g[first_var + a] += static_cast<S>(gb[a]);
  }
}

template <class D>
void push_shape_row(itp::qp::QpProblem<D>& p, int r, int first_var, double t, double h,
                    double c0, double c1, double c2) {
  using S = typename D::Scalar;
  for (int a = 0; a < 6; ++a) {
    const double v = c0 * shape(a, 0, t, h) + c1 * shape(a, 1, t, h) + c2 * shape(a, 2, t, h);
    p.push_row_entry(r, first_var + a, static_cast<S>(v));
  }
}

struct PathScenario {
  double init_l = 0.0, init_dl = 0.0, init_ddl = 0.0;  // init_sl  [m, -, 1/m]
  double obstacle_s0 = 40.0, obstacle_s1 = 55.0;       // [m]
  double obstacle_left = 1.5;   // [m] obstacle's left edge incl. margin (we pass left)
  double l_ref = 0.0;           // [m] target lateral offset
  double ddl_max = 0.1;         // [1/m] |l''| bound
  double dl_max = 0.6;          // |l'| bound at knots
  double w_offset = 10.0;       // weight of (l - l_ref)^2
};

// Path QP: 21 knots x (l, l', l''), 20 blocks of 5 m; 300 rows: per block 10
// corridor samples lo <= l + 0.2 l' <= hi and 5 samples |l''| <= ddl_max.
template <class D>
bool build_path_qp(itp::qp::QpProblem<D>& p, const PathScenario& sc) {
  using S = typename D::Scalar;
  constexpr int kBlocks = 20;
  constexpr double kH = 5.0, kHalfWidth = 0.95, kLeft = 5.25, kRight = -1.75;
  if (!p.reset(3 * (kBlocks + 1), 15 * kBlocks)) return false;
  const double w[4] = {sc.w_offset, 2.0, 20.0, 200.0};
  for (int b = 0; b < kBlocks; ++b) add_block_cost(p, 3 * b, kH, w, sc.l_ref, 0.0);
  int r = 0;
  for (int b = 0; b < kBlocks; ++b) {
    for (int k = 0; k < 10; ++k) {
      const double t = (k + 0.5) / 10.0, s = (b + t) * kH;
      push_shape_row(p, r, 3 * b, t, kH, 1.0, 0.2, 0.0);
      double lo = kRight + kHalfWidth;
      if (s >= sc.obstacle_s0 && s <= sc.obstacle_s1) lo = sc.obstacle_left + kHalfWidth;
      p.lba[r] = static_cast<S>(lo);
      p.uba[r] = static_cast<S>(kLeft - kHalfWidth);
      ++r;
    }
    for (int k = 0; k < 5; ++k) {
      const double t = (k + 0.5) / 5.0;
      push_shape_row(p, r, 3 * b, t, kH, 0.0, 0.0, 1.0);
      p.lba[r] = static_cast<S>(-sc.ddl_max);
      p.uba[r] = static_cast<S>(sc.ddl_max);
      ++r;
    }
  }
  for (int j = 0; j <= kBlocks; ++j) {
    p.lb[3 * j + 1] = static_cast<S>(-sc.dl_max);
    p.ub[3 * j + 1] = static_cast<S>(sc.dl_max);
  }
  p.lb[0] = p.ub[0] = static_cast<S>(sc.init_l);
  p.lb[1] = p.ub[1] = static_cast<S>(sc.init_dl);
  p.lb[2] = p.ub[2] = static_cast<S>(sc.init_ddl);
  return true;
}

struct SpeedScenario {
  double v0 = 15.0, a0 = 0.0;      // init_st [m/s, m/s^2]
  double v_limit = 16.7;           // [m/s]
  double v_expect = 15.0;          // [m/s]
  double lead_s0 = 30.0, lead_v = 8.0, gap = 10.0;  // follow a leading vehicle
  double a_min = -4.0, a_max = 2.0;
};

// Speed QP: 15 knots x (s, s', s''), 14 blocks of 0.5 s; 210 rows: per block
// 5 samples each of follow (s <= s_lead - gap), 0 <= s' <= v_limit, a_min <= s'' <= a_max.
template <class D>
bool build_speed_qp(itp::qp::QpProblem<D>& p, const SpeedScenario& sc) {
  using S = typename D::Scalar;
  constexpr int kBlocks = 14;
  constexpr double kH = 0.5;
  if (!p.reset(3 * (kBlocks + 1), 15 * kBlocks)) return false;
  const double w[4] = {0.0, 1.0, 1.0, 0.1};
  for (int b = 0; b < kBlocks; ++b) add_block_cost(p, 3 * b, kH, w, 0.0, sc.v_expect);
  // s_up pull: w0 (s - s_up)^2 with s_up = v_limit t, approximated per knot.
  for (int j = 0; j <= kBlocks; ++j) {
    const double wgt = 0.5;
    const int i = 3 * j;
    p.set_hessian(i, i, p.hessian(i, i) + static_cast<S>(2.0 * wgt));
    p.g[i] += static_cast<S>(-2.0 * wgt * sc.v_limit * j * kH);
  }
  int r = 0;
  for (int b = 0; b < kBlocks; ++b) {
    for (int k = 0; k < 5; ++k) {
      const double t = (k + 0.5) / 5.0, time = (b + t) * kH;
      push_shape_row(p, r, 3 * b, t, kH, 1.0, 0.0, 0.0);
      p.uba[r] = static_cast<S>(sc.lead_s0 + sc.lead_v * time - sc.gap);
      p.lba[r] = static_cast<S>(0.0);
      ++r;
      push_shape_row(p, r, 3 * b, t, kH, 0.0, 1.0, 0.0);
      p.lba[r] = static_cast<S>(0.0);
      p.uba[r] = static_cast<S>(sc.v_limit);
      ++r;
      push_shape_row(p, r, 3 * b, t, kH, 0.0, 0.0, 1.0);
      p.lba[r] = static_cast<S>(sc.a_min);
      p.uba[r] = static_cast<S>(sc.a_max);
      ++r;
    }
  }
  p.lb[0] = p.ub[0] = static_cast<S>(0.0);
  p.lb[1] = p.ub[1] = static_cast<S>(sc.v0);
  p.lb[2] = p.ub[2] = static_cast<S>(sc.a0);
  return true;
}

struct CoarseScenario {
  double l_init = 0.0, t_init = 0.0;
  double obstacle_s0 = 40.0, obstacle_s1 = 55.0, obstacle_left = 2.45;
  double v_max = 16.7;                 // [m/s]
  double wait_s = 60.0, wait_t = 5.0;  // a dynamic obstacle: reach s >= wait_s no earlier than wait_t
};

// Coarse QP (PLANNER.md eq. 2-3): x = (l_0, t_0, l_1, t_1, ...), 20 samples
// 5 m apart; bounds from the zone and t_lb; rows t_{i+1} - t_i >= ds / v_max.
template <class D>
bool build_coarse_qp(itp::qp::QpProblem<D>& p, const CoarseScenario& sc) {
  using S = typename D::Scalar;
  constexpr int kSamples = 20;
  constexpr double kDs = 5.0;
  if (!p.reset(2 * kSamples, kSamples - 1)) return false;
  auto add_h = [&](int i, int j, double v) {
    p.set_hessian(i, j, p.hessian(i, j) + static_cast<S>(v));
  };
  double t_lb[kSamples];
  for (int i = 0; i < kSamples; ++i) {
    const double s = i * kDs;
    t_lb[i] = s / sc.v_max;
    if (s >= sc.wait_s) t_lb[i] = std::max(t_lb[i], sc.wait_t + (s - sc.wait_s) / sc.v_max);
  }
  for (int v = 0; v < 2; ++v) {  // v = 0: l, 1: t
    for (int i = 1; i + 1 < kSamples; ++i) {
      const int idx[3] = {2 * (i - 1) + v, 2 * i + v, 2 * (i + 1) + v};
      const double c[3] = {1.0, -2.0, 1.0};
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b <= a; ++b) add_h(idx[a], idx[b], 2.0 * c[a] * c[b] * (a == b ? 1.0 : 1.0));
      }
    }
    for (int i = 0; i < kSamples; ++i) {
      add_h(2 * i + v, 2 * i + v, 2.0);
      p.g[2 * i + v] += static_cast<S>(v == 0 ? 0.0 : -2.0 * t_lb[i]);
    }
  }
  for (int i = 0; i < kSamples; ++i) {
    const double s = i * kDs;
    p.lb[2 * i] = static_cast<S>((s >= sc.obstacle_s0 && s <= sc.obstacle_s1) ? sc.obstacle_left : -0.8);
    p.ub[2 * i] = static_cast<S>(4.3);
    p.lb[2 * i + 1] = static_cast<S>(t_lb[i]);
  }
  p.lb[0] = p.ub[0] = static_cast<S>(sc.l_init);
  p.lb[1] = p.ub[1] = static_cast<S>(sc.t_init);
  for (int r = 0; r + 1 < kSamples; ++r) {
    p.push_row_entry(r, 2 * r + 1, static_cast<S>(-1.0));
    p.push_row_entry(r, 2 * r + 3, static_cast<S>(1.0));
    p.lba[r] = static_cast<S>(kDs / sc.v_max);
  }
  return true;
}

}  // namespace planner_qps
