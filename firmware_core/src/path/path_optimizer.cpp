#include "itp/path/path_optimizer.hpp"

#include <cmath>
#include <limits>

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"
#include "itp/decision/corridor.hpp"
#include "itp/path/lateral_move.hpp"
#include "itp/spline/quintic_block.hpp"

namespace itp::path {
namespace {

int var(int knot, int state) { return 3 * knot + state; }

// In the first block the corridor rows also admit the bumpers where the start
// state puts them (their lateral offsets at s0, linear in the heading), with
// this much room: a stitched start lies on the previous path, which a QP
// leaves on its active corridor bound, so between that path's samples it can
// be a few micrometres outside the corridor. Turning back in moves the rear
// bumper outwards first, so without the room that start was infeasible.
constexpr Scalar kStartSlack = Scalar(0.01);  // [m]

template <class Cfg>
Scalar kappa_ref_at(const BasicPathInput<Cfg>& in, Scalar s) {
  return in.kappa_ref != nullptr ? in.kappa_ref->at(s) : Scalar(0);
}

template <class Cfg>
Scalar kappa_bound_at(const BasicPathInput<Cfg>& in, Scalar s) {
  return in.kappa_bound != nullptr ? in.kappa_bound->at(s) : in.kappa_max;
}

// A start that overlaps an obstacle's box (the ego beside a car that will
// pass it, after a fallback) cannot leave it at once. The box's bound admits
// the bumpers where the start puts them over the distance a lateral move of
// `excess` takes (lateral_move.hpp), and at least the first block. Road edges
// never get this room; whether the plan is collision-free in time is the
// collision check's to decide.
template <class Cfg>
Scalar recovery_end(const BasicPathInput<Cfg>& in, Scalar excess, Scalar h, bool obstacle) {
  if (!obstacle || !(excess > Scalar(0))) return in.s0;
  const Scalar kappa = kappa_bound_at(in, in.s0) - std::fabs(kappa_ref_at(in, in.s0));
  const Scalar length = lateral_move_length(excess, kappa, in.dl_max);
  return in.s0 + (length > h ? length : h);
}

}  // namespace

template <class Cfg>
Scalar BasicPathResult<Cfg>::eval(Scalar s, int derivative) const {
  return spline::eval_spline(coefficients.data(), Cfg::kPathBlocks, h, s0, s, derivative);
}

template <class Cfg>
void BasicPathOptimizer<Cfg>::build(const ConvexSpace& space, const Decision& decision,
                          const PathInput& in, const PathWeights& w, Scalar h, bool same_matrices) {
  const Scalar inf = std::numeric_limits<Scalar>::infinity();
  qp::QpProblem<PathDims>& problem = qp_.problem();
  // H and A as the last build's (same h, reaches and weights): kept, only g
  // and the bounds are written again (the assembly was a quarter of a solve).
  if (same_matrices) {
    for (int i = 0; i < Cfg::kPathVariables; ++i) {  // Cfg::kPathVariables
      problem.g[i] = 0;
      problem.lb[i] = -inf;
      problem.ub[i] = inf;
    }
  } else {
    static_cast<void>(problem.reset(Cfg::kPathVariables, Cfg::kPathQpRows));
  }
  const spline::Matrix6 block_h =
      same_matrices ? spline::Matrix6(spline::Matrix6::Zero())
                    : spline::Matrix6(Scalar(2) * ((w.target + w.obstacle) * spline::gram(h, 0) +
                                                   w.d1 * spline::gram(h, 1) +
                                                   w.d2 * spline::gram(h, 2) + w.d3 * spline::gram(h, 3)));
  const Scalar half_width = Scalar(0.5) * in.vehicle_width;
  // The rows at the samples and the target term depend on h only: evaluated
  // once here, not again in every block (300 evaluations were 1/6 of a path solve).
  std::array<spline::Row6, Cfg::kPathSamplesPerBlock> r0s;
  std::array<spline::Row6, Cfg::kPathSamplesPerBlock> r1s;
  std::array<spline::Row6, Cfg::kPathSamplesPerBlock> r2s;
  for (int k = 0; k < Cfg::kPathSamplesPerBlock && !same_matrices; ++k) {  // samples per block
    const Scalar tau = h * static_cast<Scalar>(k) / static_cast<Scalar>(Cfg::kPathSamplesPerBlock);
    r0s[static_cast<std::size_t>(k)] = spline::evaluate_row(h, tau, 0);
    r1s[static_cast<std::size_t>(k)] = spline::evaluate_row(h, tau, 1);
    r2s[static_cast<std::size_t>(k)] = spline::evaluate_row(h, tau, 2);
  }
  const spline::Row6 target_lin = -Scalar(2) * w.target * in.l_target * spline::integral_row(h, 0, h);
  // The bumpers' lateral offsets at the start (linear in the heading, as the
  // rows), and how far past s0 each side of the corridor admits them.
  const Scalar front_now = in.l0 + in.front_reach * in.dl0;
  const Scalar rear_now = in.l0 - in.rear_reach * in.dl0;
  const decision::LateralInterval c0 = decision::corridor_at(space, decision, in.s0);
  const Scalar room_lo_end =
      recovery_end(in, c0.lo + half_width - min_of(front_now, rear_now), h, c0.lo_box != decision::kRoadEdge);
  const Scalar room_hi_end =
      recovery_end(in, max_of(front_now, rear_now) - (c0.hi - half_width), h, c0.hi_box != decision::kRoadEdge);
  int row = 0;
  for (int b = 0; b < Cfg::kPathBlocks; ++b) {  // kPathBlocks
    const int v0 = var(b, 0);
    for (int i = 0; i < 6 && !same_matrices; ++i) {    // block Hessian into the band
      for (int j = 0; j <= i; ++j) {
        static_cast<void>(problem.set_hessian(v0 + i, v0 + j, problem.hessian(v0 + i, v0 + j) + block_h(i, j)));
      }
    }
    // Linear terms: -2 w0 l_target ∫l and -2 w_obs ∫ l l_mid, l_mid constant per zone.
    const Scalar sb = in.s0 + h * static_cast<Scalar>(b);
    spline::Row6 lin = target_lin;
    for (std::int16_t zi : decision.zones) {  // <= kMaxSlices
      const decision::Zone& z = space.zones[static_cast<std::size_t>(zi)];
      const decision::Slice& zs = space.slice_of(z);
      const Scalar a = (zs.s_begin > sb ? zs.s_begin : sb) - sb;
      const Scalar e = (zs.s_end < sb + h ? zs.s_end : sb + h) - sb;
      if (e > a) {
        lin -= Scalar(2) * w.obstacle * decision::zone_reference(z, in.l_target, half_width) *
               spline::integral_row(h, a, e);
      }
    }
    // Past the corridor's end, the last zone's middle continues.
    const decision::Zone& last = space.zones[static_cast<std::size_t>(decision.zones.back())];
    const Scalar last_end = space.slice_of(last).s_end;
    if (sb + h > last_end) {
      const Scalar a = (last_end > sb ? last_end : sb) - sb;
      lin -= Scalar(2) * w.obstacle * decision::zone_reference(last, in.l_target, half_width) *
             spline::integral_row(h, a, h);
    }
    for (int i = 0; i < 6; ++i) {  // 6 block variables
      problem.g[v0 + i] += lin(i);
    }
    // Rows at the samples: corridor (8), l' and l''.
    for (int k = 0; k < Cfg::kPathSamplesPerBlock; ++k) {  // samples per block
      const Scalar tau =
          h * static_cast<Scalar>(k) / static_cast<Scalar>(Cfg::kPathSamplesPerBlock);
      const Scalar s = sb + tau;
      const spline::Row6& r0 = r0s[static_cast<std::size_t>(k)];
      const spline::Row6& r1 = r1s[static_cast<std::size_t>(k)];
      const spline::Row6& r2 = r2s[static_cast<std::size_t>(k)];
      const decision::LateralInterval c = decision::corridor_at(space, decision, s);
      const bool at_start = b == 0 && k == 0;  // fixed by init_sl: never binding
      for (int i = 0; i < 6 && !same_matrices; ++i) {  // rows touch the 6 block variables
        static_cast<void>(problem.push_row_entry(row, v0 + i, r0(i) + in.front_reach * r1(i)));
        static_cast<void>(problem.push_row_entry(row + 1, v0 + i, r0(i) - in.rear_reach * r1(i)));
        static_cast<void>(problem.push_row_entry(row + 2, v0 + i, r1(i)));
        static_cast<void>(problem.push_row_entry(row + 3, v0 + i, r2(i)));
      }
      for (int end = 0; end < 2; ++end) {  // front and rear bumper rows of (8)
        problem.lba[row + end] = at_start ? -inf : c.lo + half_width;
        problem.uba[row + end] = at_start ? inf : c.hi - half_width;
        if (problem.lba[row + end] > problem.uba[row + end]) {  // just the vehicle's width: its middle
          problem.lba[row + end] = problem.uba[row + end] = c.mid();
        }
        const Scalar now = end == 0 ? front_now : rear_now;
        if (!at_start && (b == 0 || (s <= room_lo_end && c.lo_box == c0.lo_box))) {
          problem.lba[row + end] = min_of(problem.lba[row + end], now - kStartSlack);
        }
        if (!at_start && (b == 0 || (s <= room_hi_end && c.hi_box == c0.hi_box))) {
          problem.uba[row + end] = max_of(problem.uba[row + end], now + kStartSlack);
        }
      }
      problem.lba[row + 2] = at_start ? -inf : -in.dl_max;
      problem.uba[row + 2] = at_start ? inf : in.dl_max;
      const Scalar kr = kappa_ref_at(in, s);
      const Scalar kb = kappa_bound_at(in, s);
      problem.lba[row + 3] = at_start ? -inf : -kb - kr;
      problem.uba[row + 3] = at_start ? inf : kb - kr;
      row += Cfg::kPathRowsPerSample;
    }
  }
  // Knot bounds: the start is init_sl; elsewhere l' and l'' as the rows.
  for (int j = 1; j < Cfg::kPathKnots; ++j) {  // kPathBlocks
    const Scalar s = in.s0 + h * static_cast<Scalar>(j);
    const Scalar kr = kappa_ref_at(in, s);
    const Scalar kb = kappa_bound_at(in, s);
    problem.lb[var(j, 1)] = -in.dl_max;
    problem.ub[var(j, 1)] = in.dl_max;
    problem.lb[var(j, 2)] = -kb - kr;
    problem.ub[var(j, 2)] = kb - kr;
  }
  problem.lb[var(0, 0)] = problem.ub[var(0, 0)] = in.l0;
  problem.lb[var(0, 1)] = problem.ub[var(0, 1)] = in.dl0;
  problem.lb[var(0, 2)] = problem.ub[var(0, 2)] = in.ddl0;
}

template <class Cfg>
void BasicPathOptimizer<Cfg>::solve(const ConvexSpace& space, const Decision& decision,
                                    const PathInput& in, const PathWeights& w, PathResult& out,
                                    int max_iterations) {
  out = PathResult{};
  const Scalar h = in.length / static_cast<Scalar>(Cfg::kPathBlocks);
  if (decision.zones.empty() || !(h > 0) || !std::isfinite(in.l0) || !std::isfinite(in.dl0) ||
      !std::isfinite(in.ddl0)) {
    out.status = qp::QpStatus::kInvalidInput;
    return;
  }
  // H and A depend only on h, the bumper reaches and the weights, never on the corridor:
  // hotstart whenever they match (new g and bounds only).
  const PathMatrixKey key{h, in.front_reach, in.rear_reach, w};
  const bool same = qp_.same_matrices(key);
  build(space, decision, in, w, h, same);
  if (observer_ != nullptr && observer_->path != nullptr) {
    observer_->path(observer_->context, qp_.problem());
  }
  // A path QP that failed (infeasible, at the iteration cap, or in numerical
  // trouble) still leaves a valid factor of H, and its working set is where
  // the corridor pinches: the next solve, usually the same corridor at the
  // steering limit, hotstarts from it instead of cold (e.g. 2 or 17-30
  // iterations where cold hit the cap of 60).
  const qp::QpStatus st = qp_.solve(key, /*keep_factor_after_failure=*/true, max_iterations);
  out.status = st;
  out.iterations = qp_.result().iterations;
  out.s0 = in.s0;
  out.h = h;
  if (qp::is_usable(st)) {
    for (int i = 0; i < Cfg::kPathVariables; ++i) {  // Cfg::kPathVariables
      out.knots[static_cast<std::size_t>(i)] = qp_.result().x[i];
    }
    spline::block_coefficients(h, out.knots.data(), Cfg::kPathBlocks, out.coefficients.data());
  }
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)            \
  template struct BasicPathResult<C>; \
  template class BasicPathOptimizer<C>;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::path
