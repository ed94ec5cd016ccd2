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
#include "itp/scene/obstacle_motion.hpp"
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

// One planning call: the scene and the time it is planned at (the scene's
// clock: dynamic obstacles' predictions are sampled from `now` on).
template <class Cfg>
struct BasicPlanRequest {
  const scene::BasicScene<Cfg>* scene = nullptr;
  Scalar now = 0;  // [s]
};

// The planner for configuration Cfg (itp/config.hpp); all of its memory is
// in the object (about 1 MB with DefaultConfig: place it in static storage).
template <class Cfg>
class BasicPlanner {
 public:
  using Config = Cfg;
  using Scene = scene::BasicScene<Cfg>;
  using Plan = BasicPlan<Cfg>;
  using PlanRequest = BasicPlanRequest<Cfg>;
  using QpObserver = qp::BasicPlannerQpObserver<Cfg>;
  using ReferenceLine = geometry::BasicReferenceLine<Cfg>;
  using DecisionStage = decision::BasicDecisionStage<Cfg>;
  using Decision = decision::BasicDecision<Cfg>;
  using CoarseInput = decision::BasicCoarseInput<Cfg>;
  using CurvatureProfile = decision::BasicCurvatureProfile<Cfg>;
  using RoadSl = decision::BasicRoadSl<Cfg>;
  using PathOptimizer = path::BasicPathOptimizer<Cfg>;
  using PathInput = path::BasicPathInput<Cfg>;
  using PathResult = path::BasicPathResult<Cfg>;
  using SpeedOptimizer = speed::BasicSpeedOptimizer<Cfg>;
  using SpeedResult = speed::BasicSpeedResult<Cfg>;
  using SpeedBounds = speed::BasicSpeedBounds<Cfg>;
  using StGraph = speed::BasicStGraph<Cfg>;
  using DynamicTrack = speed::BasicDynamicTrack<Cfg>;
  using CoarseResult = decision::BasicCoarseResult<Cfg>;
  using DynamicObstacle = scene::BasicDynamicObstacle<Cfg>;
  using SpeedInput = speed::BasicSpeedInput<Cfg>;
  using StDecision = speed::BasicStDecision<Cfg>;
  using StParams = speed::BasicStParams<Cfg>;
  using StSamples = std::array<Scalar, Cfg::kStSamples>;  // one value per ST sample

  void set_tick_source(TickSource ticks) { ticks_ = ticks; }
  // Host tools: see every QP this planner solves (null: none). Must outlive the planner's use.
  void set_qp_observer(const QpObserver* observer) {
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
  const DecisionStage& decision_stage() const { return decision_; }
  const PathResult& path_result() const { return path_; }
  const SpeedResult& speed_result() const { return speed_; }
  const StGraph& st_graph() const { return st_; }
  const ReferenceLine& reference_line() const { return reference_; }
  const PathOptimizer& path_optimizer() const { return path_opt_; }
  const SpeedOptimizer& speed_optimizer() const { return speed_opt_; }
  const SpeedBounds& speed_bounds() const { return bounds_; }
  // SL boxes of the last iteration: static ones (inflated by the ego's extents
  // in s), then the dynamic ones at their meeting places.
  std::span<const decision::SlBox> boxes() const { return boxes_.span(); }
  int chosen_decision() const { return chosen_; }
  Scalar path_start() const { return s_start_; }  // [m]
  Scalar path_length() const { return length_; }  // [m]

 private:
  // The trajectory is sampled at the ST samples: every 0.1 s over the horizon.
  static constexpr int kSamples = Cfg::kStSamples;
  static constexpr Scalar kDt =
      Cfg::kSpeedHorizon / static_cast<Scalar>(Cfg::kSpeedSamples);  // [s]
  static_assert(kSamples == Cfg::kTrajectorySamples, "speed samples are the trajectory samples");

  struct Start {       // init_sl and init_st
    Scalar s = 0;      // [m]
    Scalar l = 0, dl = 0, ddl = 0;
    Scalar v = 0, a = 0;  // [m/s], [m/s^2]
    Scalar stitched_age = -1;  // [s] age of the previous plan it was stitched from; < 0: not stitched
  };

  bool prepare(const Scene& scene, Scalar now, Plan& out);
  Start start_state(const Scene& scene, Scalar now) const;
  void project_obstacles(const Scene& scene, Scalar now);
  void keep_on_road(Scalar s, decision::SlBox& box) const;
  int place_dynamic(const StSamples& s_guess, bool* skip);
  std::uint64_t corridor_signature(const Decision& d, const PathInput& pi) const;
  bool known_infeasible(std::uint64_t corridor) const;
  int nearest_dynamic(std::size_t n_static, const bool* skip, Scalar s_lo, Scalar s_hi) const;
  Scalar blocking_slice_end(Scalar reach) const;
  Scalar stop_before(Scalar reach) const;
  FallbackReason decide_path(const StSamples& s_guess, std::size_t n_static,
                             const decision::ConvexSpaceParams& cp, const CoarseInput& ci,
                             PathInput& pi, Plan& out);
  bool iterate(const Scene& scene, const Start& start, Plan& out);
  void plan_speed(const StParams& stp, const StSamples& s_guess, const StSamples& v_guess,
                  SpeedInput& si, Plan& out);
  void sample_trajectory(const Start& start, Plan& out) const;
  int first_collision(const Scene& scene, const Plan& plan, std::int32_t* hit_id) const;
  bool follower_runs_in(const Plan& plan, std::size_t k, const scene::ObstacleSample& o,
                        const scene::ObstacleSample* before) const;
  void fallback(const Scene* scene, Scalar now, FallbackReason reason, Plan& out);
  void record_decisions(Plan& out) const;
  int rank_decisions(std::array<int, Cfg::kKeptDecisions>& order) const;
  Scalar hysteresis_bonus(int index) const;
  void update_kappa_bound(const StSamples& s_guess, const StSamples& v_guess);
  void update_kappa_reach(CurvatureProfile& out, Scalar v0, Scalar a_lat) const;

  TickSource ticks_{};
  PlannerSettings settings_{};
  Scalar now_ = 0;  // [s] time of the current request

  geometry::BasicSmoothingSplineWorkspace<Cfg> spline_ws_{};
  ReferenceLine reference_{};
  CurvatureProfile kappa_{};
  CurvatureProfile kappa_bound_{};  // |κ| the path may have at the expected speed
  CurvatureProfile kappa_reach_{};  // ... at the slowest speed braking can reach there
  CurvatureProfile kappa_evasive_{};  // ... with the evasive lateral acceleration
  RoadSl road_{};
  decision::VehicleLimits limits_{};
  geometry::Point2 origin_{};  // [m] first reference point (s = 0) of the last prepared cycle
  Scalar lane_target_ = 0;  // [m] target lane centre
  Scalar s_start_ = 0;   // [m] path start (the ego's s)
  Scalar ego_l_ = 0;     // [m] the ego's lateral offset
  Scalar ego_v_ = 0;     // [m/s] the ego's speed
  Scalar length_ = 0;    // [m] path length this cycle
  Scalar map_end_ = 0;   // [m] path s where the reference line (the map) ends
  Scalar front_ = 0;     // [m] rear axle to front bumper
  Scalar rear_ = 0;      // [m] rear overhang

  // Obstacles in SL: static boxes, then the dynamic ones at their meeting time.
  StaticVector<decision::SlBox, Cfg::kMaxObstacles> boxes_;
  std::array<DynamicTrack, Cfg::kMaxDynamicObstacles> tracks_{};
  // Each dynamic obstacle's motion at the ST samples, as planned against
  // (road_prediction.hpp); the collision check uses it too.
  std::array<std::array<scene::ObstacleSample, Cfg::kStSamples>, Cfg::kMaxDynamicObstacles> motion_{};
  int track_count_ = 0;

  DecisionStage decision_{};
  PathOptimizer path_opt_{};
  PathResult path_{};
  StGraph st_{};
  SpeedBounds bounds_{};
  SpeedOptimizer speed_opt_{};
  SpeedResult speed_{};
  // Corridors whose path QP failed at the steering limit this cycle (skipped when met again).
  StaticVector<std::uint64_t, Cfg::kRememberedInfeasibleCorridors> infeasible_;
  int path_solves_ = 0;  // path QPs solved this cycle (<= kMaxPathSolvesPerCycle)
  int decision_runs_ = 0;  // decision-stage runs this cycle (<= kMaxDecisionRunsPerCycle)
  int chosen_ = -1;  // decision index in decision_.decisions().kept
  bool blocked_ = false;  // the chosen corridor ends before the horizon
  bool blocked_by_statics_ = false;  // ... at static obstacles alone (not waiting for traffic)
  bool evasive_ = false;  // the chosen path needs the evasive lateral acceleration

  // The previous cycle's output, for stitching and fallbacks.
  Plan previous_{};
  Scalar previous_time_ = 0;
  bool have_previous_ = false;   // previous_ holds the last ok plan
  bool last_cycle_ok_ = false;   // path_/speed_ are that plan's (stitching needs them)
  bool holding_fallback_l_ = false;
  Scalar fallback_l_ = 0;        // [m] lateral offset held by consecutive fallbacks
};

using PlanRequest = BasicPlanRequest<DefaultConfig>;
using Planner = BasicPlanner<DefaultConfig>;

}  // namespace itp::planner
