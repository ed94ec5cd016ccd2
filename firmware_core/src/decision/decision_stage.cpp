#include "itp/decision/decision_stage.hpp"

#include "itp/configurations.hpp"

namespace itp::decision {

const char* to_string(DecisionStatus status) {
  switch (status) {
    case DecisionStatus::kOk: return "ok";
    case DecisionStatus::kBlocked: return "blocked";
    case DecisionStatus::kNoDecision: return "no_decision";
    case DecisionStatus::kInvalidInput: return "invalid_input";
  }
  return "unknown";
}

template <class Cfg>
DecisionStatus BasicDecisionStage<Cfg>::run(const RoadSl& road, std::span<const SlBox> boxes,
                                            const ConvexSpaceParams& params,
                                            const CoarseInput& input,
                                            const DecisionWeights& weights) {
  DecisionWork work;
  const DecisionBudget unlimited{Cfg::kMaxTreeNodes, Cfg::kKeptDecisions, Cfg::kKeptDecisions * Cfg::kCoarseQpMaxIterations};
  return run(road, boxes, params, input, weights, unlimited, TickSource{}, work);
}

template <class Cfg>
DecisionStatus BasicDecisionStage<Cfg>::run(const RoadSl& road, std::span<const SlBox> boxes,
                                            const ConvexSpaceParams& params, const CoarseInput& input,
                                            const DecisionWeights& weights, const DecisionBudget& budget,
                                            TickSource ticks, DecisionWork& work) {
  work = DecisionWork{};
  best_ = -1;
  set_.kept.clear();
  const ConvexSpaceStatus cs = build_convex_space(road, boxes, params, space_);
  if (cs == ConvexSpaceStatus::kInvalidInput) {
    return DecisionStatus::kInvalidInput;
  }
  if (cs != ConvexSpaceStatus::kOk) {
    return DecisionStatus::kNoDecision;
  }
  enumerate_decisions(space_, weights.geometric, set_, budget.tree_nodes);
  work.tree_nodes = set_.nodes_expanded;
  const std::uint64_t t0 = ticks.ticks();
  // Lowest decision cost wins; ties keep the better geometric rank. Decisions
  // beyond the budget stay unevaluated (not usable).
  // WCET: <= kKeptDecisions; over the cycle <= kMaxCoarseQpsPerCycle QPs with
  // kMaxCoarseIterationsPerCycle iterations in all (the budget the caller passes),
  // and within the cycle's QP work (budget.ledger).
  for (std::size_t i = 0; i < set_.kept.size(); ++i) {  // <= kKeptDecisions
    int left = budget.coarse_iterations - work.coarse_iterations;
    if (budget.ledger != nullptr) {
      left = budget.ledger->grant(Cfg::kCoarseQpSetupWork, Cfg::kCoarseIterationWork, left);
    }
    if (work.coarse_qps >= budget.coarse_qps || left <= 0) {
      coarse_[i] = CoarseResult{};  // kInvalidInput: not usable
      work.budget_out = true;
      continue;
    }
    evaluator_.evaluate(space_, set_.kept[i], input, weights.coarse, coarse_[i], left);
    ++work.coarse_qps;
    work.coarse_iterations += coarse_[i].qp_iterations;
    if (budget.ledger != nullptr) {
      budget.ledger->charge(Cfg::kCoarseQpSetupWork, Cfg::kCoarseIterationWork, coarse_[i].qp_iterations);
    }
    if (!qp::is_usable(coarse_[i].status)) {
      continue;
    }
    if (best_ < 0 || coarse_[i].decision_cost < coarse_[static_cast<std::size_t>(best_)].decision_cost) {
      best_ = static_cast<int>(i);
    }
  }
  work.coarse_ticks = ticks.ticks() - t0;
  if (best_ < 0) {
    return DecisionStatus::kNoDecision;
  }
  return set_.kept[static_cast<std::size_t>(best_)].reaches_end ? DecisionStatus::kOk
                                                               : DecisionStatus::kBlocked;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C) template class BasicDecisionStage<C>;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::decision
