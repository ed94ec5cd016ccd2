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
  best_ = -1;
  set_.kept.clear();
  const ConvexSpaceStatus cs = build_convex_space(road, boxes, params, space_);
  if (cs == ConvexSpaceStatus::kInvalidInput) {
    return DecisionStatus::kInvalidInput;
  }
  if (cs != ConvexSpaceStatus::kOk) {
    return DecisionStatus::kNoDecision;
  }
  enumerate_decisions(space_, weights.geometric, set_);
  // Lowest decision cost wins; ties keep the better geometric rank.
  for (std::size_t i = 0; i < set_.kept.size(); ++i) {  // <= kKeptDecisions
    evaluator_.evaluate(space_, set_.kept[i], input, weights.coarse, coarse_[i]);
    if (!qp::is_usable(coarse_[i].status)) {
      continue;
    }
    if (best_ < 0 || coarse_[i].decision_cost < coarse_[static_cast<std::size_t>(best_)].decision_cost) {
      best_ = static_cast<int>(i);
    }
  }
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
