#include "itp/speed/speed_optimizer.hpp"

#include <cmath>
#include <limits>

#include "itp/configurations.hpp"
#include "itp/spline/quintic_block.hpp"

namespace itp::speed {
namespace {

int var(int knot, int state) { return 3 * knot + state; }

template <class Cfg>
bool finite_bounds(const BasicSpeedBounds<Cfg>& b) {
  for (int k = 0; k <= Cfg::kSpeedSamples; ++k) {  // Cfg::kSpeedSamples + 1
    const auto u = static_cast<std::size_t>(k);
    if (std::isnan(b.s_lo[u]) || std::isnan(b.s_hi[u]) || std::isnan(b.v_lo[u]) ||
        std::isnan(b.v_hi[u]) || !std::isfinite(b.s_ref[u]) || !std::isfinite(b.v_ref[u])) {
      return false;
    }
  }
  return true;
}

}  // namespace

template <class Cfg>
Scalar BasicSpeedResult<Cfg>::eval(Scalar t, int derivative) const {
  return spline::eval_spline(coefficients.data(), Cfg::kSpeedBlocks, h, Scalar(0), t, derivative);
}

template <class Cfg>
void BasicSpeedOptimizer<Cfg>::build(const SpeedInput& in, const SpeedBounds& bd, const SpeedWeights& w,
                           Scalar h, bool same_matrices) {
  const Scalar inf = std::numeric_limits<Scalar>::infinity();
  qp::QpProblem<SpeedDims>& problem = qp_.problem();
  // H and A as the last build's (same h and weights): kept, only g and the
  // bounds are written again (every bound is, below).
  if (same_matrices) {
    for (int i = 0; i < Cfg::kSpeedVariables; ++i) {  // Cfg::kSpeedVariables
      problem.g[i] = 0;
    }
  } else {
    static_cast<void>(problem.reset(Cfg::kSpeedVariables, Cfg::kSpeedQpRows));
  }
  const spline::Matrix6 block_h =
      same_matrices ? spline::Matrix6(spline::Matrix6::Zero())
                    : spline::Matrix6(Scalar(2) * (w.s_up * spline::gram(h, 0) + w.v * spline::gram(h, 1) +
                                                   w.a * spline::gram(h, 2) + w.jerk * spline::gram(h, 3)));
  const int per = Cfg::kSpeedSamplesPerBlock;
  // The rows at the samples depend on h only: evaluated once, not per block.
  std::array<spline::Row6, Cfg::kSpeedSamplesPerBlock> r0s;
  std::array<spline::Row6, Cfg::kSpeedSamplesPerBlock> r1s;
  std::array<spline::Row6, Cfg::kSpeedSamplesPerBlock> r2s;
  for (int k = 0; k < per && !same_matrices; ++k) {  // samples per block
    const Scalar tau = h * static_cast<Scalar>(k) / static_cast<Scalar>(per);
    r0s[static_cast<std::size_t>(k)] = spline::evaluate_row(h, tau, 0);
    r1s[static_cast<std::size_t>(k)] = spline::evaluate_row(h, tau, 1);
    r2s[static_cast<std::size_t>(k)] = spline::evaluate_row(h, tau, 2);
  }
  int row = 0;
  for (int b = 0; b < Cfg::kSpeedBlocks; ++b) {  // kSpeedBlocks
    const int v0 = var(b, 0);
    for (int i = 0; i < 6 && !same_matrices; ++i) {  // block Hessian into the band
      for (int j = 0; j <= i; ++j) {
        static_cast<void>(problem.set_hessian(v0 + i, v0 + j, problem.hessian(v0 + i, v0 + j) + block_h(i, j)));
      }
    }
    // References linear inside the block, through their values at its ends.
    const auto k0 = static_cast<std::size_t>(b * per);
    const auto k1 = static_cast<std::size_t>((b + 1) * per);
    const Scalar s_slope = (bd.s_ref[k1] - bd.s_ref[k0]) / h;
    const Scalar v_slope = (bd.v_ref[k1] - bd.v_ref[k0]) / h;
    const spline::Row6 lin = -Scalar(2) * (w.s_up * spline::linear_moment(h, bd.s_ref[k0], s_slope, 0) +
                                           w.v * spline::linear_moment(h, bd.v_ref[k0], v_slope, 1));
    for (int i = 0; i < 6; ++i) {  // 6 block variables
      problem.g[v0 + i] += lin(i);
    }
    for (int k = 0; k < per; ++k) {  // samples per block
      const auto u = static_cast<std::size_t>(b * per + k);
      const spline::Row6& r0 = r0s[static_cast<std::size_t>(k)];
      const spline::Row6& r1 = r1s[static_cast<std::size_t>(k)];
      const spline::Row6& r2 = r2s[static_cast<std::size_t>(k)];
      for (int i = 0; i < 6 && !same_matrices; ++i) {  // rows touch the 6 block variables
        static_cast<void>(problem.push_row_entry(row, v0 + i, r0(i)));
        static_cast<void>(problem.push_row_entry(row + 1, v0 + i, r1(i)));
        static_cast<void>(problem.push_row_entry(row + 2, v0 + i, r2(i)));
      }
      const bool at_start = b == 0 && k == 0;  // fixed by init_st
      problem.lba[row] = at_start ? -inf : bd.s_lo[u];
      problem.uba[row] = at_start ? inf : bd.s_hi[u];
      problem.lba[row + 1] = at_start ? -inf : bd.v_lo[u];
      problem.uba[row + 1] = at_start ? inf : bd.v_hi[u];
      problem.lba[row + 2] = at_start ? -inf : in.a_min;
      problem.uba[row + 2] = at_start ? inf : in.a_max;
      row += 3;
    }
  }
  for (int j = 1; j < Cfg::kSpeedKnots; ++j) {  // knots after the start
    const auto u = static_cast<std::size_t>(j * per);
    problem.lb[var(j, 0)] = bd.s_lo[u];
    problem.ub[var(j, 0)] = bd.s_hi[u];
    problem.lb[var(j, 1)] = bd.v_lo[u];
    problem.ub[var(j, 1)] = bd.v_hi[u];
    problem.lb[var(j, 2)] = in.a_min;
    problem.ub[var(j, 2)] = in.a_max;
  }
  problem.lb[var(0, 0)] = problem.ub[var(0, 0)] = 0;
  problem.lb[var(0, 1)] = problem.ub[var(0, 1)] = in.v0;
  problem.lb[var(0, 2)] = problem.ub[var(0, 2)] = in.a0;
}

template <class Cfg>
void BasicSpeedOptimizer<Cfg>::solve(const SpeedInput& in, const SpeedBounds& bounds,
                                     const SpeedWeights& w, SpeedResult& out, int max_iterations) {
  out = SpeedResult{};
  const Scalar h = in.horizon / static_cast<Scalar>(Cfg::kSpeedBlocks);
  if (!(h > 0) || !std::isfinite(in.v0) || !std::isfinite(in.a0) || !finite_bounds(bounds)) {
    out.status = qp::QpStatus::kInvalidInput;
    return;
  }
  // H and A depend only on h and the weights: hotstart whenever they match.
  const SpeedMatrixKey key{h, w};
  build(in, bounds, w, h, qp_.same_matrices(key));
  if (observer_ != nullptr && observer_->speed != nullptr) {
    observer_->speed(observer_->context, qp_.problem());
  }
  const qp::QpStatus st = qp_.solve(key, false, max_iterations);
  out.status = st;
  out.iterations = qp_.result().iterations;
  out.h = h;
  if (qp::is_usable(st)) {
    for (int i = 0; i < Cfg::kSpeedVariables; ++i) {  // Cfg::kSpeedVariables
      out.knots[static_cast<std::size_t>(i)] = qp_.result().x[i];
    }
    spline::block_coefficients(h, out.knots.data(), Cfg::kSpeedBlocks, out.coefficients.data());
  }
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)             \
  template struct BasicSpeedResult<C>; \
  template class BasicSpeedOptimizer<C>;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::speed
