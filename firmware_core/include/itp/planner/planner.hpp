#pragma once
// The iterative triple-optimization planner (paper §2): one object that owns
// all of its memory; plan() runs convex space → decision → path QP → ST graph
// → speed QP, checks the result with the real footprints, and iterates with
// updated meeting times until collision-free and converged (or the
// compile-time iteration limit). It never allocates, never throws and always
// returns a usable trajectory: bad input and failures give a safe stop.
#include <array>

#include "itp/core/tick_source.hpp"
#include "itp/decision/decision_stage.hpp"
#include "itp/geometry/reference_line.hpp"
#include "itp/path/path_optimizer.hpp"
#include "itp/planner/plan.hpp"
#include "itp/scene/scene.hpp"
#include "itp/speed/speed_optimizer.hpp"
#include "itp/speed/st_graph.hpp"

namespace itp::planner {

// Tuning that does not change memory: margins, comfort limits, weights.
struct PlannerSettings {
  Scalar static_margin = Scalar(0.3);    // [m] SL inflation of static obstacles
  Scalar dynamic_margin = Scalar(0.5);   // [m] SL inflation of dynamic obstacles
  Scalar road_margin = Scalar(0.15);     // [m] kept from the road edges (tracking error)
  Scalar comfort_decel = Scalar(-3.0);   // [m/s^2] planning braking limit (the scene's a_min is the hard one)
  Scalar comfort_accel = Scalar(2.0);    // [m/s^2] planning acceleration limit
  Scalar stop_margin = Scalar(2.0);      // [m] kept before a blocked corridor
  Scalar converge_s = Scalar(0.5);       // [m] iteration stops when s(t) moved less than this
  Scalar converge_l = Scalar(0.1);       // [m] ... and l(s) less than this
  Scalar replan_lateral = Scalar(0.5);   // [m] stitch from the previous plan within these deviations
  Scalar replan_longitudinal = Scalar(1.5);  // [m]
  Scalar replan_speed = Scalar(1.0);     // [m/s]
  Scalar hysteresis = Scalar(0.3);       // decision-cost bonus for keeping last cycle's sides
  Scalar blocked_lane_weight = Scalar(1.0);  // [1/m] decision-cost per metre a blocked stop is off the target lane
  decision::DecisionWeights decision_weights{};
  path::PathWeights path_weights{};
  speed::SpeedWeights speed_weights{};
};

// One planning call: the scene and the time it is planned at (the scene's
// clock: dynamic obstacles' predictions are sampled from `now` on).
struct PlanRequest {
  const scene::Scene* scene = nullptr;
  Scalar now = 0;  // [s]
};

class Planner {
 public:
  void set_tick_source(TickSource ticks) { ticks_ = ticks; }
  // Host tools: see every QP this planner solves (null: none). Must outlive the planner's use.
  void set_qp_observer(const qp::PlannerQpObserver* observer) {
    decision_.set_observer(observer);
    path_opt_.set_observer(observer);
    speed_opt_.set_observer(observer);
  }
  PlannerSettings& settings() { return settings_; }
  // Forget the previous plan (no stitching, no hysteresis on the next call).
  // Back to the state of a new planner: no previous plan (no stitching, no
  // hysteresis) and no QP factorisations to hotstart from, so that the next
  // cycle's output depends on its input alone.
  void reset();

  PlanStatus plan(const PlanRequest& request, Plan& out);

  // Read-only views for tools (planner_cli, plots): the last cycle's stages.
  const decision::DecisionStage& decision_stage() const { return decision_; }
  const path::PathResult& path_result() const { return path_; }
  const speed::SpeedResult& speed_result() const { return speed_; }
  const speed::StGraph& st_graph() const { return st_; }
  const geometry::ReferenceLine& reference_line() const { return reference_; }
  const path::PathOptimizer& path_optimizer() const { return path_opt_; }
  const speed::SpeedOptimizer& speed_optimizer() const { return speed_opt_; }
  const speed::SpeedBounds& speed_bounds() const { return bounds_; }
  // SL boxes of the last iteration: static ones (inflated by the ego's extents
  // in s), then the dynamic ones at their meeting places.
  std::span<const decision::SlBox> boxes() const { return boxes_.span(); }
  int chosen_decision() const { return chosen_; }
  Scalar path_start() const { return s_start_; }  // [m]
  Scalar path_length() const { return length_; }  // [m]

 private:
  struct Start {       // init_sl and init_st
    Scalar s = 0;      // [m]
    Scalar l = 0, dl = 0, ddl = 0;
    Scalar v = 0, a = 0;  // [m/s], [m/s^2]
    Scalar stitched_age = -1;  // [s] age of the previous plan it was stitched from; < 0: not stitched
  };

  bool prepare(const scene::Scene& scene, Scalar now, Plan& out);
  Start start_state(const scene::Scene& scene, Scalar now) const;
  void project_obstacles(const scene::Scene& scene, Scalar now);
  void keep_on_road(Scalar s, decision::SlBox& box) const;
  int place_dynamic(const std::array<Scalar, speed::kStSamples>& s_guess, bool* skip);
  std::uint64_t corridor_signature(const decision::Decision& d, const path::PathInput& pi) const;
  bool known_infeasible(std::uint64_t corridor) const;
  int nearest_dynamic(std::size_t n_static, const bool* skip, bool at_reach_only, Scalar reach) const;
  FallbackReason decide_path(const std::array<Scalar, speed::kStSamples>& s_guess, std::size_t n_static,
                             const decision::ConvexSpaceParams& cp, const decision::CoarseInput& ci,
                             path::PathInput& pi, Plan& out);
  bool iterate(const scene::Scene& scene, const Start& start, Plan& out);
  void sample_trajectory(const Start& start, Plan& out) const;
  int first_collision(const scene::Scene& scene, Scalar now, const Plan& plan) const;
  void fallback(const scene::Scene* scene, Scalar now, FallbackReason reason, Plan& out);
  void record_decisions(Plan& out) const;
  int rank_decisions(std::array<int, config::kKeptDecisions>& order) const;
  Scalar hysteresis_bonus(int index) const;
  void update_kappa_bound(const std::array<Scalar, speed::kStSamples>& s_guess,
                          const std::array<Scalar, speed::kStSamples>& v_guess);

  TickSource ticks_{};
  PlannerSettings settings_{};
  Scalar now_ = 0;  // [s] time of the current request

  geometry::SmoothingSplineWorkspace spline_ws_{};
  geometry::ReferenceLine reference_{};
  decision::CurvatureProfile kappa_{};
  decision::CurvatureProfile kappa_bound_{};  // |κ| the path may have at the expected speed
  decision::RoadSl road_{};
  decision::VehicleLimits limits_{};
  Scalar lane_target_ = 0;  // [m] target lane centre
  Scalar s_start_ = 0;   // [m] path start (the ego's s)
  Scalar length_ = 0;    // [m] path length this cycle
  Scalar front_ = 0;     // [m] rear axle to front bumper
  Scalar rear_ = 0;      // [m] rear overhang

  // Obstacles in SL: static boxes, then the dynamic ones at their meeting time.
  StaticVector<decision::SlBox, config::kMaxObstacles> boxes_;
  std::array<speed::DynamicTrack, config::kMaxDynamicObstacles> tracks_{};
  int track_count_ = 0;

  decision::DecisionStage decision_{};
  path::PathOptimizer path_opt_{};
  path::PathResult path_{};
  speed::StGraph st_{};
  speed::SpeedBounds bounds_{};
  speed::SpeedOptimizer speed_opt_{};
  speed::SpeedResult speed_{};
  // Corridors whose path QP failed at the steering limit this cycle (skipped when met again).
  StaticVector<std::uint64_t, config::kRememberedInfeasibleCorridors> infeasible_;
  int path_solves_ = 0;  // path QPs solved this cycle (<= kMaxPathSolvesPerCycle)
  int decision_runs_ = 0;  // decision-stage runs this cycle (<= kMaxDecisionRunsPerCycle)
  int chosen_ = -1;  // decision index in decision_.decisions().kept
  bool blocked_ = false;  // the chosen corridor ends at static obstacles

  // The previous cycle's output, for stitching and fallbacks.
  Plan previous_{};
  Scalar previous_time_ = 0;
  bool have_previous_ = false;   // previous_ holds the last ok plan
  bool last_cycle_ok_ = false;   // path_/speed_ are that plan's (stitching needs them)
  bool holding_fallback_l_ = false;
  Scalar fallback_l_ = 0;        // [m] lateral offset held by consecutive fallbacks
};

}  // namespace itp::planner
