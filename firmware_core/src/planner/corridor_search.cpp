#include "itp/planner/corridor_search.hpp"

#include <cmath>

#include "itp/configurations.hpp"
#include "itp/decision/corridor.hpp"

namespace itp::planner {
namespace {

constexpr int kMaxPathAttempts = 4;   // decisions tried by the path QP per round
constexpr int kEvasiveAttempts = 2;   // ... of which this many with the evasive bound too
constexpr Scalar kEverywhere = Scalar(1e9);  // [m] an s-range without bounds

}  // namespace

template <class Cfg>
void BasicCorridorSearch<Cfg>::begin_cycle() {
  chosen_ = -1;
  infeasible_.clear();
  path_solves_ = 0;
  path_iterations_ = 0;
  decision_runs_ = 0;
  tree_nodes_ = 0;
  coarse_qps_ = 0;
  coarse_iterations_ = 0;
  path_budget_out_ = false;
}

template <class Cfg>
FallbackReason BasicCorridorSearch<Cfg>::run(const StSamples& s_guess, BasicSlScene<Cfg>& sl,
                                             const Context& ctx, PathResult& path, BasicPlan<Cfg>& out) {
  bool skip[Cfg::kMaxDynamicObstacles] = {};
  chosen_ = -1;
  evasive_ = false;
  // WCET: <= kMaxDynamicObstacles + 1 rounds per call, and over the cycle
  // <= kMaxDecisionRunsPerCycle runs (decision_runs_, checked first).
  for (int round = 0; round <= Cfg::kMaxDynamicObstacles; ++round) {  // one more left-out obstacle per round
    if (decision_budget_spent()) {
      return FallbackReason::kBudget;  // the worst case stays bounded (WCET): the caller falls back
    }
    ++decision_runs_;
    std::uint64_t t0 = ctx.ticks.ticks();
    sl.place_dynamic(s_guess, skip);
    const decision::DecisionBudget budget{Cfg::kMaxTreeNodesPerCycle - tree_nodes_, Cfg::kMaxCoarseQpsPerCycle - coarse_qps_,
                                          Cfg::kMaxCoarseIterationsPerCycle - coarse_iterations_, ctx.work};
    decision::DecisionWork work;
    const decision::DecisionStatus ds = stage_.run(sl.road(), sl.boxes(), ctx.inputs->convex, ctx.inputs->coarse,
                                                   ctx.settings->decision_weights, budget, ctx.ticks, work);
    tree_nodes_ += work.tree_nodes;
    coarse_qps_ += work.coarse_qps;
    coarse_iterations_ += work.coarse_iterations;
    ++out.timing.decision_runs;
    out.timing.tree_nodes += work.tree_nodes;
    out.timing.coarse_qps += work.coarse_qps;
    out.timing.coarse_iterations += work.coarse_iterations;
    out.timing.coarse += work.coarse_ticks;
    out.qp_solves += work.coarse_qps;
    out.qp_iterations += work.coarse_iterations;
    out.timing.decision += ctx.ticks.ticks() - t0;
    if (ds == decision::DecisionStatus::kInvalidInput) {
      return FallbackReason::kNoDecision;
    }
    int drop = -1;
    if ((ds == decision::DecisionStatus::kNoDecision || stage_.best() < 0) && work.budget_out) {
      return FallbackReason::kBudget;  // no decision evaluated within the coarse-QP budget
    }
    if (ds == decision::DecisionStatus::kNoDecision || stage_.best() < 0) {
      drop = sl.nearest_dynamic(skip, -kEverywhere, kEverywhere);
      if (drop < 0) {
        return FallbackReason::kNoDecision;
      }
    } else if (ds == decision::DecisionStatus::kBlocked) {
      // The best corridor ends where the next slice has no zone it links to:
      // a moving obstacle in that slice is left to the ST graph; none there
      // means the ego waits (for traffic in its sweep) or static obstacles
      // block the road (a real stop).
      const Decision& best = stage_.decisions().kept[static_cast<std::size_t>(stage_.best())];
      drop = sl.nearest_dynamic(skip, best.reach, blocking_slice_end(best.reach));
    }
    if (drop < 0) {
      if (try_paths(sl, ctx, path, out)) {
        return FallbackReason::kNone;
      }
      if (path_budget_out_) {
        return FallbackReason::kBudget;  // the worst case stays bounded (WCET): the caller falls back
      }
      drop = sl.nearest_dynamic(skip, -kEverywhere, kEverywhere);
      if (drop < 0) {
        return FallbackReason::kPathQpFailed;
      }
    }
    skip[drop] = true;
  }
  return FallbackReason::kPathQpFailed;
}

template <class Cfg>
bool BasicCorridorSearch<Cfg>::try_paths(BasicSlScene<Cfg>& sl, const Context& ctx, PathResult& path,
                                         BasicPlan<Cfg>& out) {
  if (path_iterations_left(ctx.work) <= 0) {
    path_budget_out_ = true;
    return false;
  }
  const std::uint64_t t0 = ctx.ticks.ticks();
  path::BasicPathInput<Cfg> pi = ctx.inputs->path;
  std::array<int, Cfg::kKeptDecisions> order{};
  const int candidates = rank_decisions(stage_, sl.boxes(), ctx.previous, *ctx.settings, sl.lane_target(), order);
  for (int attempt = 0; attempt < candidates && attempt < kMaxPathAttempts && chosen_ < 0; ++attempt) {
    const int index = order[static_cast<std::size_t>(attempt)];
    const Decision& d = stage_.decisions().kept[static_cast<std::size_t>(index)];
    const std::uint64_t corridor = corridor_signature(d, pi);
    if (known_infeasible(corridor)) {
      continue;  // this corridor failed at the steering limit earlier in this cycle
    }
    // The curvature bound at the expected speed, then at the slowest speed
    // braking can reach, then (the two best decisions only) the same with
    // the evasive lateral acceleration: a plan that needs it is a fallback
    // (evasive), the safest way out, not a stop where the ego stands (in an
    // oncoming lane, say). Within the cycle's budget.
    const int levels = attempt < kEvasiveAttempts ? 3 : 2;
    // WCET: <= 3 per attempt; over the cycle <= kMaxPathSolvesPerCycle solves
    // and kMaxPathIterationsPerCycle iterations in all, within the cycle's QP
    // work (path_iterations_left).
    for (int relax = 0; relax < levels && chosen_ < 0; ++relax) {
      // Capped at what is left of the cycle's path-QP iterations and QP work.
      const int cap = path_iterations_left(ctx.work);
      if (cap <= 0) {
        break;
      }
      ++path_solves_;
      pi.kappa_bound = relax == 0 ? &ctx.bounds->expected : (relax == 1 ? &ctx.bounds->reach : &ctx.bounds->evasive);
      path_opt_.solve(stage_.space(), d, pi, ctx.settings->path_weights, path, cap);
      path_iterations_ += path.iterations;
      if (ctx.work != nullptr) {
        ctx.work->charge(Cfg::kPathSolveSetupWork, Cfg::kPathIterationWork, path.iterations);
      }
      ++out.qp_solves;
      out.qp_iterations += path.iterations;
      ++out.timing.path_solves;
      out.timing.path_iterations += path.iterations;
      if (qp::is_usable(path.status)) {
        chosen_ = index;
        evasive_ = relax == 2;
      }
    }
    if (chosen_ < 0 && path_iterations_left(ctx.work) <= 0) {
      path_budget_out_ = true;
      break;  // budget spent: the worst case stays bounded (WCET), the caller falls back
    }
    if (chosen_ < 0 && !infeasible_.full()) {
      // Not full: checked in the condition (kRememberedInfeasibleCorridors = capacity).
      static_cast<void>(infeasible_.push_back(corridor));
    }
  }
  out.timing.path += ctx.ticks.ticks() - t0;
  return chosen_ >= 0;
}

// A fingerprint of a decision's corridor as the path QP sees it: the
// bounds at its samples (to the millimetre). Within one cycle the path QP
// depends on nothing else (the start state is fixed), so a corridor that
// failed at every curvature bound fails again in a later iteration or round.
template <class Cfg>
std::uint64_t BasicCorridorSearch<Cfg>::corridor_signature(const Decision& d,
                                                           const path::BasicPathInput<Cfg>& pi) const {
  constexpr std::uint64_t kFnvPrime = 1099511628211ull;
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a offset basis
  const int samples = Cfg::kPathBlocks * Cfg::kPathSamplesPerBlock;
  for (int k = 0; k <= samples; ++k) {  // the path QP's samples
    const Scalar s = pi.s0 + pi.length * static_cast<Scalar>(k) / static_cast<Scalar>(samples);
    const decision::LateralInterval c = decision::corridor_at(stage_.space(), d, s);
    const auto lo = static_cast<std::int64_t>(std::lround(c.lo * Scalar(1000)));
    const auto hi = static_cast<std::int64_t>(std::lround(c.hi * Scalar(1000)));
    h = (h ^ static_cast<std::uint64_t>(lo)) * kFnvPrime;
    h = (h ^ static_cast<std::uint64_t>(hi)) * kFnvPrime;
  }
  return h;
}

template <class Cfg>
bool BasicCorridorSearch<Cfg>::known_infeasible(std::uint64_t corridor) const {
  for (const std::uint64_t c : infeasible_) {  // <= kRememberedInfeasibleCorridors
    if (c == corridor) {
      return true;
    }
  }
  return false;
}

template <class Cfg>
Scalar BasicCorridorSearch<Cfg>::blocking_slice_end(Scalar reach) const {
  for (const decision::Slice& slice : stage_.space().slices) {  // <= kMaxSlices
    if (slice.s_begin >= reach) {
      return slice.s_end;
    }
  }
  return reach;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C) template class BasicCorridorSearch<C>;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::planner
