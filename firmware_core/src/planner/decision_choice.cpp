#include "itp/planner/decision_choice.hpp"

#include <cmath>

#include "itp/configurations.hpp"
#include "itp/decision/decision_tree.hpp"

namespace itp::planner {
namespace {

LateralSide lateral_side(decision::Side side) {
  return side == decision::Side::kLeft ? LateralSide::kLeft
         : side == decision::Side::kRight ? LateralSide::kRight
                                          : LateralSide::kNone;
}

// Frame-to-frame consistency: a decision that passes every obstacle of the
// previous cycle's plan on the same side as that plan did earns a bonus, so
// that near-equal alternatives do not flip between cycles. Passing a moving
// obstacle on the other side than the last plan costs far more: the path
// would swing across its lane within a second or two (lateral acceleration
// beyond any limit when tracked), so any decision that keeps those sides is
// tried first.
template <class Cfg>
Scalar hysteresis_bonus(const decision::BasicConvexSpace<Cfg>& space, const decision::BasicDecision<Cfg>& d,
                        std::span<const geometry::SlBox> boxes, const PreviousSides& previous,
                        const PlannerSettings& settings) {
  if (previous.decisions.empty()) {
    return 0;
  }
  int compared = 0;
  bool static_flip = false;
  for (const geometry::SlBox& b : boxes) {  // <= kMaxObstacles
    for (const ObstacleDecision& od : previous.decisions) {  // <= kMaxObstacles
      if (od.obstacle != b.obstacle_id || od.dynamic != b.dynamic || od.lateral == LateralSide::kNone) {
        continue;
      }
      const LateralSide now = lateral_side(decision::side_of(space, d, b));
      if (now != od.lateral && now != LateralSide::kNone) {
        if (b.dynamic) {
          return -settings.moving_side_flip_cost;
        }
        static_flip = true;
      }
      ++compared;
    }
  }
  return compared > 0 && !static_flip ? settings.hysteresis : Scalar(0);
}

}  // namespace

template <class Cfg>
int rank_decisions(const decision::BasicDecisionStage<Cfg>& stage, std::span<const geometry::SlBox> boxes,
                   const PreviousSides& previous, const PlannerSettings& settings, Scalar lane_target,
                   std::array<int, Cfg::kKeptDecisions>& order) {
  std::array<Scalar, Cfg::kKeptDecisions> cost{};
  int n = 0;
  for (std::size_t i = 0; i < stage.decisions().kept.size(); ++i) {  // <= kKeptDecisions
    const decision::CoarseScore& cr = stage.coarse(i);
    if (!qp::is_usable(cr.status)) {
      continue;
    }
    const decision::BasicDecision<Cfg>& d = stage.decisions().kept[i];
    Scalar c = cr.decision_cost - hysteresis_bonus(stage.space(), d, boxes, previous, settings);
    if (!d.reaches_end && cr.samples > 0) {
      // A stop before a blockage waits in the target lane, not half-way into
      // another one (where oncoming traffic may come).
      c += settings.blocked_lane_weight * std::fabs(cr.l_end - lane_target);
    }
    cost[static_cast<std::size_t>(n)] = c;
    order[static_cast<std::size_t>(n)] = static_cast<int>(i);
    ++n;
  }
  for (int i = 1; i < n; ++i) {  // insertion sort, stable; n <= kKeptDecisions
    const Scalar c = cost[static_cast<std::size_t>(i)];
    const int o = order[static_cast<std::size_t>(i)];
    int j = i - 1;
    for (; j >= 0 && cost[static_cast<std::size_t>(j)] > c; --j) {
      cost[static_cast<std::size_t>(j + 1)] = cost[static_cast<std::size_t>(j)];
      order[static_cast<std::size_t>(j + 1)] = order[static_cast<std::size_t>(j)];
    }
    cost[static_cast<std::size_t>(j + 1)] = c;
    order[static_cast<std::size_t>(j + 1)] = o;
  }
  return n;
}

template <class Cfg>
void record_decisions(const decision::BasicDecisionStage<Cfg>& stage, int chosen,
                      std::span<const geometry::SlBox> boxes,
                      std::span<const speed::BasicStDecision<Cfg>> st_decisions, BasicPlan<Cfg>& out) {
  out.decisions.clear();
  if (chosen < 0) {
    return;
  }
  const decision::BasicDecision<Cfg>& d = stage.decisions().kept[static_cast<std::size_t>(chosen)];
  for (const geometry::SlBox& b : boxes) {  // <= kMaxObstacles
    ObstacleDecision od;
    od.obstacle = b.obstacle_id;
    od.dynamic = b.dynamic;
    od.lateral = lateral_side(decision::side_of(stage.space(), d, b));
    // Cleared above; boxes <= kMaxDecisionObstacles <= kMaxObstacles = capacity.
    static_cast<void>(out.decisions.push_back(od));
  }
  for (const speed::BasicStDecision<Cfg>& sd : st_decisions) {  // <= kMaxDynamicObstacles
    bool found = false;
    for (ObstacleDecision& od : out.decisions) {  // <= kMaxObstacles
      if (od.obstacle == sd.id && od.dynamic) {
        od.longitudinal = sd.decision;
        found = true;
      }
    }
    if (!found) {
      ObstacleDecision od;
      od.obstacle = sd.id;
      od.dynamic = true;
      od.longitudinal = sd.decision;
      // One entry per obstacle (ids unique: validation) <= kMaxObstacles = capacity.
      static_cast<void>(out.decisions.push_back(od));
    }
  }
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                        \
  template int rank_decisions<C>(const decision::BasicDecisionStage<C>&,                          \
                                 std::span<const geometry::SlBox>, const PreviousSides&,          \
                                 const PlannerSettings&, Scalar, std::array<int, C::kKeptDecisions>&); \
  template void record_decisions<C>(const decision::BasicDecisionStage<C>&, int,                  \
                                    std::span<const geometry::SlBox>,                             \
                                    std::span<const speed::BasicStDecision<C>>, BasicPlan<C>&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::planner
