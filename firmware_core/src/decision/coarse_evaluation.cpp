#include "itp/decision/coarse_evaluation.hpp"

#include <cmath>
#include <limits>

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"
#include "itp/decision/corridor.hpp"

namespace itp::decision {
namespace {

constexpr int kSubSteps = 4;                       // kinematic pass: sub-steps per sample interval
template <class Cfg>
constexpr int kFine = (Cfg::kCoarseSamples - 1) * kSubSteps + 1;  // points of the kinematic pass
constexpr Scalar kMinSpeed = Scalar(0.1);          // [m/s] floor when integrating 1/v

constexpr int l_var(int i) { return 2 * i; }
constexpr int t_var(int i) { return 2 * i + 1; }


template <class D>
void add_hessian(qp::QpProblem<D>& p, int i, int j, Scalar v) {
  static_cast<void>(p.set_hessian(i, j, p.hessian(i, j) + v));
}

// Adds w (x_a - 2 x_b + x_c)² to H.
template <class D>
void add_second_difference(qp::QpProblem<D>& p, int a, int b, int c, Scalar w) {
  const int idx[3] = {a, b, c};
  const Scalar coef[3] = {Scalar(1), Scalar(-2), Scalar(1)};
  for (int r = 0; r < 3; ++r) {    // 3 x 3 outer product
    for (int q = 0; q <= r; ++q) {
      add_hessian(p, idx[r], idx[q], w * coef[r] * coef[q]);
    }
  }
}

struct Moments {
  Scalar mean_abs = 0;
  Scalar var = 0;
};

Moments moments(const Scalar* v, int n) {
  Moments m;
  if (n <= 0) {
    return m;
  }
  Scalar sum = 0;
  Scalar sum_abs = 0;
  for (int i = 0; i < n; ++i) {  // n <= kCoarseSamples
    sum += v[i];
    sum_abs += std::fabs(v[i]);
  }
  const Scalar mean = sum / static_cast<Scalar>(n);
  Scalar var = 0;
  for (int i = 0; i < n; ++i) {  // n <= kCoarseSamples
    var += (v[i] - mean) * (v[i] - mean);
  }
  m.mean_abs = sum_abs / static_cast<Scalar>(n);
  m.var = var / static_cast<Scalar>(n);
  return m;
}

}  // namespace

template <class Cfg>
void earliest_arrival(const BasicCoarseInput<Cfg>& in, Scalar s0, Scalar ds, int count,
                      bool stop_at_end, Scalar* t_lb) {
  const int fine = (count - 1) * kSubSteps + 1;
  const Scalar h = ds / static_cast<Scalar>(kSubSteps);
  std::array<Scalar, kFine<Cfg>> v{};
  for (int j = 0; j < fine; ++j) {  // <= kFine: the speed each point allows
    const Scalar s = s0 + h * static_cast<Scalar>(j);
    const Scalar kappa = in.kappa_ref != nullptr ? in.kappa_ref->at(s) : Scalar(0);
    v[static_cast<std::size_t>(j)] = curve_speed_limit(in.limits, kappa);
  }
  if (stop_at_end) {
    v[static_cast<std::size_t>(fine - 1)] = 0;
  }
  // Forward: accelerate from the current speed.
  v[0] = min_of(v[0], max_of(in.v_init, Scalar(0)));
  for (int j = 1; j < fine; ++j) {  // < kFine
    const Scalar reach = std::sqrt(v[static_cast<std::size_t>(j - 1)] * v[static_cast<std::size_t>(j - 1)] +
                                   Scalar(2) * in.limits.a_max * h);
    v[static_cast<std::size_t>(j)] = min_of(v[static_cast<std::size_t>(j)], reach);
  }
  // Backward: brake in time for every later limit.
  for (int j = fine - 2; j >= 0; --j) {  // < kFine
    const Scalar brake = std::sqrt(v[static_cast<std::size_t>(j + 1)] * v[static_cast<std::size_t>(j + 1)] -
                                   Scalar(2) * in.limits.a_min * h);
    v[static_cast<std::size_t>(j)] = min_of(v[static_cast<std::size_t>(j)], brake);
  }
  Scalar t = 0;
  t_lb[0] = 0;
  for (int j = 1; j < fine; ++j) {  // < kFine: trapezoid on 1/v
    const Scalar vm = max_of(Scalar(0.5) * (v[static_cast<std::size_t>(j - 1)] + v[static_cast<std::size_t>(j)]), kMinSpeed);
    t += h / vm;
    if (j % kSubSteps == 0) {
      t_lb[j / kSubSteps] = t;
    }
  }
}

template <class Cfg>
bool BasicCoarseEvaluator<Cfg>::sample_corridor(const ConvexSpace& space, const Decision& decision,
                                                const CoarseInput& in, CoarseResult& out) const {
  const Scalar s0 = space.s_start;
  const Scalar s_last = decision.reaches_end
                            ? space.s_end
                            : max_of(s0 + Scalar(1), decision.reach - in.stop_margin);
  out.samples = kN;
  out.ds = (s_last - s0) / static_cast<Scalar>(kN - 1);
  const Scalar half = Scalar(0.5) * in.vehicle_width + in.lateral_margin;
  for (int i = 0; i < kN; ++i) {  // kCoarseSamples
    const Scalar s = s0 + out.ds * static_cast<Scalar>(i);
    out.s[static_cast<std::size_t>(i)] = s;
    const LateralInterval corridor = corridor_at(space, decision, s);
    Scalar lo = corridor.lo + half;
    Scalar hi = corridor.hi - half;
    if (lo > hi) {  // the zone is just the vehicle's width: keep to its middle
      lo = hi = Scalar(0.5) * (lo + hi);
    }
    out.l_lb[static_cast<std::size_t>(i)] = lo;
    out.l_ub[static_cast<std::size_t>(i)] = hi;
  }
  earliest_arrival(in, s0, out.ds, kN, !decision.reaches_end, out.t_lb.data());
  return true;
}

template <class Cfg>
void BasicCoarseEvaluator<Cfg>::build_qp(const CoarseInput& in, const CoarseWeights& w,
                                         const CoarseResult& out) {
  const Scalar inf = std::numeric_limits<Scalar>::infinity();
  qp::QpProblem<CoarseDims>& problem = qp_.problem();
  static_cast<void>(problem.reset(2 * kN, kN - 1));
  for (int i = 0; i < kN; ++i) {  // kCoarseSamples
    add_hessian(problem, l_var(i), l_var(i), w.qp.l_ref);
    add_hessian(problem, t_var(i), t_var(i), w.qp.t_lb);
    problem.g[l_var(i)] = -w.qp.l_ref * in.l_ref;
    problem.g[t_var(i)] = -w.qp.t_lb * out.t_lb[static_cast<std::size_t>(i)];
    problem.lb[l_var(i)] = out.l_lb[static_cast<std::size_t>(i)];
    problem.ub[l_var(i)] = out.l_ub[static_cast<std::size_t>(i)];
    problem.lb[t_var(i)] = out.t_lb[static_cast<std::size_t>(i)];
    problem.ub[t_var(i)] = inf;
    if (i >= 1 && i + 1 < kN) {
      add_second_difference(problem, l_var(i - 1), l_var(i), l_var(i + 1), w.qp.l_smooth);
      add_second_difference(problem, t_var(i - 1), t_var(i), t_var(i + 1), w.qp.t_smooth);
    }
  }
  // The start is fixed (eq. 3): l_0 = l_init, t_0 = 0.
  problem.lb[l_var(0)] = problem.ub[l_var(0)] = in.l_init;
  problem.lb[t_var(0)] = problem.ub[t_var(0)] = 0;
  // Time runs forward no faster than the speed limit allows.
  const Scalar dt_min = out.ds / max_of(in.limits.speed_limit, kMinSpeed);
  for (int i = 0; i + 1 < kN; ++i) {  // kCoarseSamples - 1 rows
    static_cast<void>(problem.push_row_entry(i, t_var(i), Scalar(-1)));
    static_cast<void>(problem.push_row_entry(i, t_var(i + 1), Scalar(1)));
    problem.lba[i] = dt_min;
    problem.uba[i] = inf;
  }
}

template <class Cfg>
void BasicCoarseEvaluator<Cfg>::score(const Decision& decision, const CoarseInput& in,
                                      const CoarseWeights& w, CoarseResult& out) const {
  std::array<Scalar, Cfg::kCoarseSamples> kappa{};
  std::array<Scalar, Cfg::kCoarseSamples> a_lat{};
  std::array<Scalar, Cfg::kCoarseSamples> a_lon{};
  const Scalar ds = out.ds;
  int count = 0;
  for (int i = 1; i + 1 < kN; ++i) {  // interior samples
    const auto u = static_cast<std::size_t>(i);
    const Scalar dt_prev = max_of(out.t[u] - out.t[u - 1], Scalar(1e-3));
    const Scalar dt_next = max_of(out.t[u + 1] - out.t[u], Scalar(1e-3));
    const Scalar v_prev = ds / dt_prev;
    const Scalar v_next = ds / dt_next;
    const Scalar v = Scalar(0.5) * (v_prev + v_next);
    const Scalar kref = in.kappa_ref != nullptr ? in.kappa_ref->at(out.s[u]) : Scalar(0);
    const Scalar k = (out.l[u - 1] - Scalar(2) * out.l[u] + out.l[u + 1]) / (ds * ds) + kref;
    kappa[static_cast<std::size_t>(count)] = k;
    a_lat[static_cast<std::size_t>(count)] = v * v * k;
    a_lon[static_cast<std::size_t>(count)] = (v_next - v_prev) / (Scalar(0.5) * (dt_prev + dt_next));
    ++count;
  }
  const Moments mk = moments(kappa.data(), count);
  const Moments mlat = moments(a_lat.data(), count);
  const Moments mlon = moments(a_lon.data(), count);
  out.kappa_mean = mk.mean_abs;
  out.kappa_var = mk.var;
  out.a_lat_mean = mlat.mean_abs;
  out.a_lat_var = mlat.var;
  out.a_lon_mean = mlon.mean_abs;
  out.a_lon_var = mlon.var;
  out.path_cost = w.kappa_mean * mk.mean_abs + w.kappa_var * mk.var;
  out.dynamic_cost = w.a_lat_mean * mlat.mean_abs + w.a_lat_var * mlat.var +
                     w.a_lon_mean * mlon.mean_abs + w.a_lon_var * mlon.var;
  out.decision_cost = decision.geometric_cost + out.path_cost + out.dynamic_cost;
}

template <class Cfg>
void BasicCoarseEvaluator<Cfg>::evaluate(const ConvexSpace& space, const Decision& decision,
                                         const CoarseInput& in, const CoarseWeights& w,
                                         CoarseResult& out, int max_iterations) {
  out = CoarseResult{};
  if (decision.zones.empty() || !sample_corridor(space, decision, in, out)) {
    out.status = qp::QpStatus::kInvalidInput;
    return;
  }
  build_qp(in, w, out);
  if (observer_ != nullptr && observer_->coarse != nullptr) {
    observer_->coarse(observer_->context, qp_.problem());
  }
  // H does not depend on the decision (only on the weights), so after the
  // first factorisation every solve is a hotstart: new g and bounds only.
  const qp::QpStatus st = qp_.solve(w.qp, false, max_iterations);
  out.status = st;
  out.qp_iterations = qp_.result().iterations;
  if (!qp::is_usable(st)) {
    out.decision_cost = std::numeric_limits<Scalar>::infinity();
    return;
  }
  for (int i = 0; i < kN; ++i) {  // kCoarseSamples
    out.l[static_cast<std::size_t>(i)] = qp_.result().x[l_var(i)];
    out.t[static_cast<std::size_t>(i)] = qp_.result().x[t_var(i)];
  }
  out.l_end = out.samples > 0 ? out.l[static_cast<std::size_t>(out.samples - 1)] : Scalar(0);
  score(decision, in, w, out);
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                \
  template class BasicCoarseEvaluator<C>; \
  template void earliest_arrival<C>(const BasicCoarseInput<C>&, Scalar, Scalar, int, bool, Scalar*);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::decision
