#pragma once
// The planner's tuning: margins, comfort limits, thresholds and weights.
// Changing them changes behaviour, never memory.
#include "itp/config.hpp"
#include "itp/decision/decision_stage.hpp"
#include "itp/path/path_optimizer.hpp"
#include "itp/speed/speed_optimizer.hpp"

namespace itp::planner {

// Tuning that does not change memory: margins, comfort limits, weights.
struct PlannerSettings {
  Scalar static_margin = Scalar(0.3);    // [m] SL inflation of static obstacles
  Scalar dynamic_margin = Scalar(0.5);   // [m] SL inflation of dynamic obstacles
  Scalar road_margin = Scalar(0.15);     // [m] kept from the road edges (tracking error)
  // Convex space (decision::select_road_cuts): a stretch of the horizon is
  // cut where the road's edges change when it loses more than this width to
  // the change ...
  Scalar road_cut_tolerance = Scalar(0.1);  // [m]
  // ... and no road cut leaves a slice shorter than this.
  Scalar road_cut_min_slice = Scalar(4.0);  // [m]
  Scalar comfort_decel = Scalar(-3.0);   // [m/s^2] planning braking limit (the scene's a_min is the hard one)
  Scalar comfort_accel = Scalar(2.0);    // [m/s^2] planning acceleration limit
  Scalar stop_margin = Scalar(2.0);      // [m] kept before a blocked corridor
  Scalar converge_s = Scalar(0.5);       // [m] iteration stops when s(t) moved less than this
  Scalar converge_l = Scalar(0.1);       // [m] ... and l(s) less than this
  Scalar replan_lateral = Scalar(0.5);   // [m] stitch from the previous plan within these deviations
  Scalar replan_longitudinal = Scalar(1.5);  // [m]
  Scalar replan_speed = Scalar(1.0);     // [m/s]
  Scalar hysteresis = Scalar(0.3);       // decision-cost bonus for keeping last cycle's sides
  Scalar moving_side_flip_cost = Scalar(100);  // decision cost of passing a moving obstacle on the other side than last cycle
  // [m/s^2] the lateral acceleration a path may need when no path within
  // lat_acc_max exists: the plan is then a fallback (evasive), not a stop
  // where the ego stands (in an oncoming lane, say).
  Scalar evasive_lat_acc = Scalar(3.8);
  Scalar blocked_lane_weight = Scalar(1.0);  // [1/m] decision-cost per metre a blocked stop is off the target lane
  decision::DecisionWeights decision_weights{};
  path::PathWeights path_weights{};
  speed::SpeedWeights speed_weights{};
};

}  // namespace itp::planner
