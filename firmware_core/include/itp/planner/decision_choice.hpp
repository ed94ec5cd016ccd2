#pragma once
// Which of the K kept decisions the path QP tries first (paper 1.1, eq. 4,
// plus frame-to-frame consistency), and the per-obstacle decisions a plan
// reports (plan/1 "decision").
#include <array>
#include <span>

#include "itp/decision/decision_stage.hpp"
#include "itp/geometry/sl_box.hpp"
#include "itp/planner/plan.hpp"
#include "itp/planner/planner_settings.hpp"

namespace itp::planner {

// What the ranking remembers of the last plan: the sides it passed obstacles
// on (empty: no recent plan, no hysteresis).
struct PreviousSides {
  std::span<const ObstacleDecision> decisions;
};

// Kept decisions with a usable coarse QP, in the order the path QP tries
// them: decision cost (eq. 4) minus the hysteresis bonus, plus, for a
// corridor that ends (a stop), blocked_lane_weight per metre its stop is off
// the target lane; ties keep the geometric rank. Returns how many.
template <class Cfg>
int rank_decisions(const decision::BasicDecisionStage<Cfg>& stage, std::span<const geometry::SlBox> boxes,
                   const PreviousSides& previous, const PlannerSettings& settings, Scalar lane_target,
                   std::array<int, Cfg::kKeptDecisions>& order);

// The decisions of the plan: the chosen corridor's side of every SL box and
// the ST graph's longitudinal decision of every dynamic obstacle.
template <class Cfg>
void record_decisions(const decision::BasicDecisionStage<Cfg>& stage, int chosen,
                      std::span<const geometry::SlBox> boxes,
                      std::span<const speed::BasicStDecision<Cfg>> st_decisions, BasicPlan<Cfg>& out);

}  // namespace itp::planner
