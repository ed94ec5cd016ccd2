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
  input_ = input;
  weights_ = weights.coarse;
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
      scores_[i] = CoarseScore{};  // kInvalidInput: not usable
      work.budget_out = true;
      continue;
    }
    evaluator_.evaluate(space_, set_.kept[i], input, weights.coarse, result_, left);
    scores_[i] = static_cast<const CoarseScore&>(result_);
    ++work.coarse_qps;
    work.coarse_iterations += scores_[i].qp_iterations;
    if (budget.ledger != nullptr) {
      budget.ledger->charge(Cfg::kCoarseQpSetupWork, Cfg::kCoarseIterationWork, scores_[i].qp_iterations);
    }
    if (!qp::is_usable(scores_[i].status)) {
      continue;
    }
    if (best_ < 0 || scores_[i].decision_cost < scores_[static_cast<std::size_t>(best_)].decision_cost) {
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

template <class Cfg>
void BasicDecisionStage<Cfg>::evaluate_again(std::size_t i, CoarseEvaluator& evaluator, CoarseResult& out) const {
  out = CoarseResult{};
  if (i >= set_.kept.size()) {
    return;  // kInvalidInput
  }
  evaluator.reset();
  evaluator.evaluate(space_, set_.kept[i], input_, weights_, out);
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C) template class BasicDecisionStage<C>;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::decision
