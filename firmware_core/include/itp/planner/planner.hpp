#pragma once
// The iterative triple-optimization planner (paper §2): one object that owns
// all of its memory; plan() runs convex space → decision → path QP → ST graph
// → speed QP, checks the result with the real footprints, and iterates with
// updated meeting times until collision-free and converged (or the
// compile-time iteration limit). It never allocates, never throws and always
// returns a usable trajectory: bad input and failures give a safe stop.
#include <array>
#include <span>
#include <type_traits>

#include "itp/core/tick_source.hpp"
#include "itp/geometry/reference_line.hpp"
#include "itp/geometry/smoothing_spline.hpp"
#include "itp/planner/curvature_bounds.hpp"
#include "itp/planner/cycle_inputs.hpp"
#include "itp/planner/iteration.hpp"
#include "itp/planner/plan.hpp"
#include "itp/planner/planner_settings.hpp"
#include "itp/planner/safe_stop.hpp"
#include "itp/planner/sl_scene.hpp"
#include "itp/scene/scene.hpp"

namespace itp::planner {

// One planning call: the scene and the time it is planned at (the scene's
// clock: dynamic obstacles' predictions are sampled from `now` on).
template <class Cfg>
struct BasicPlanRequest {
  const scene::BasicScene<Cfg>* scene = nullptr;
  Scalar now = 0;  // [s]
};

// The planner for configuration Cfg (itp/config.hpp); all of its memory is
// in the object (place it in static storage; sizeof in docs/performance.md).
// One cycle: validate the scene, fit the reference line, put the scene in
// its frame (sl_scene.hpp), find where to start (the ego state, or the
// previous plan's point at this time: stitching), iterate (iteration.hpp),
// and stop safely (safe_stop.hpp) when no trajectory came out.
template <class Cfg>
class BasicPlanner {
 public:
  using Config = Cfg;
  using Scene = scene::BasicScene<Cfg>;
  using Plan = BasicPlan<Cfg>;
  using PlanRequest = BasicPlanRequest<Cfg>;
  using QpObserver = qp::BasicPlannerQpObserver<Cfg>;
  using ReferenceLine = geometry::BasicReferenceLine<Cfg>;
  using Iteration = BasicIteration<Cfg>;
  using DecisionStage = decision::BasicDecisionStage<Cfg>;
  using PathOptimizer = path::BasicPathOptimizer<Cfg>;
  using PathResult = path::BasicPathResult<Cfg>;
  using SpeedOptimizer = speed::BasicSpeedOptimizer<Cfg>;
  using SpeedResult = speed::BasicSpeedResult<Cfg>;
  using SpeedBounds = speed::BasicSpeedBounds<Cfg>;
  using StGraph = speed::BasicStGraph<Cfg>;

  void set_tick_source(TickSource ticks) { ticks_ = ticks; }
  // Host tools: see every QP this planner solves (null: none). Must outlive the planner's use.
  void set_qp_observer(const QpObserver* observer) { iteration_.set_observer(observer); }
  PlannerSettings& settings() { return settings_; }
  // Back to the state of a new planner: no previous plan (no stitching, no
  // hysteresis) and no QP factorisations to hotstart from, so that the next
  // cycle's output depends on its input alone.
  void reset();

  // One cycle. The plan stays in the planner until the next plan() or
  // reset() (a firmware encodes it from there; no second copy).
  const Plan& plan(const PlanRequest& request);
  // The same, copied to `out` (host tools).
  PlanStatus plan(const PlanRequest& request, Plan& out) {
    out = plan(request);
    return out.status;
  }

  // With one shared QP storage (Cfg::kShareQpStorage) its bytes are free
  // between plan() calls: the firmware reassembles its next request in
  // them (app/firmware_service.hpp). Lending ends the stages' holds, so
  // each rebuilds its problem and restarts warm on its next claim (the
  // first QP of a cycle does so anyway when they share). `holder` asks
  // lent_to() whether a plan() used the bytes since it borrowed them.
  static constexpr std::size_t kLendableBytes = qp::PlannerQpArenas<Cfg>::kLendableBytes;
  // Without shared storage there is nothing to lend (kLendableBytes 0):
  // lend() gives no bytes and lent_to() is false.
  std::span<unsigned char> lend(const void* holder) {
    if constexpr (Cfg::kShareQpStorage) {
      return iteration_.qp_arenas().shared.claim_bytes(holder);
    } else {
      return {};
    }
  }
  bool lent_to(const void* holder) const {
    if constexpr (Cfg::kShareQpStorage) {
      return iteration_.qp_arenas().shared.held_by(holder);
    } else {
      return false;
    }
  }

  // Read-only views for tools (planner_cli, plots): the last cycle's stages.
  const DecisionStage& decision_stage() const { return iteration_.search().stage(); }
  const PathResult& path_result() const { return iteration_.path(); }
  const SpeedResult& speed_result() const { return iteration_.speed(); }
  const StGraph& st_graph() const { return iteration_.st_graph(); }
  const ReferenceLine& reference_line() const { return reference_; }
  const PathOptimizer& path_optimizer() const { return iteration_.search().path_optimizer(); }
  const SpeedOptimizer& speed_optimizer() const { return iteration_.speed_optimizer(); }
  const SpeedBounds& speed_bounds() const { return iteration_.speed_bounds(); }
  // SL boxes of the last iteration: static ones (inflated by the ego's extents
  // in s), then the dynamic ones at their meeting places.
  std::span<const geometry::SlBox> boxes() const { return sl_.boxes(); }
  int chosen_decision() const { return iteration_.search().chosen(); }
  Scalar path_start() const { return sl_.s_start(); }  // [m]
  Scalar path_length() const { return length_; }       // [m]

 private:
  bool prepare(const Scene& scene, Scalar now, Plan& out);
  StartState start_state(const Scene& scene, Scalar now) const;
  void stop_safely(const Scene* scene, Scalar now, FallbackReason reason, Plan& out);
  Scalar stop_before_map_end() const;

  TickSource ticks_{};
  PlannerSettings settings_{};

  // The reference spline's workspace, used only while prepare() fits the
  // reference line, before any QP: in the QP storage when that is shared.
  using SplineWorkspace = geometry::BasicSmoothingSplineWorkspace<Cfg>;
  struct InQpStorage {};
  SplineWorkspace& spline_workspace();
  [[no_unique_address]] std::conditional_t<Cfg::kShareQpStorage, InQpStorage, SplineWorkspace> spline_ws_{};
  ReferenceLine reference_{};
  geometry::Point2 origin_{};  // [m] first reference point (s = 0) of the last prepared cycle
  BasicSlScene<Cfg> sl_{};
  BasicCurvatureBounds<Cfg> kappa_{};
  decision::MotionLimits limits_{};
  Scalar length_ = 0;   // [m] SL horizon this cycle
  Scalar map_end_ = 0;  // [m] path s where the reference line (the map) ends
  Iteration iteration_{};

  // The previous cycle's output, for stitching, hysteresis and fallbacks.
  Plan previous_{};
  Scalar previous_time_ = 0;
  bool have_previous_ = false;  // previous_ holds the last ok plan
  bool last_cycle_ok_ = false;  // the iteration's path and speed are that plan's (stitching needs them)
  FallbackMemory fallback_memory_{};

  // The last request (scene and time, scene/scene_digest.hpp) and its
  // outcome: the same request again gets the same plan (issue 13, defect 11)
  // instead of a plan stitched onto itself.
  std::uint64_t last_digest_ = 0;
  bool have_last_digest_ = false;
  // This cycle's output while it is planned, then the last output (repeated
  // for the same scene). An ok one is copied to previous_.
  Plan output_{};
};

using PlanRequest = BasicPlanRequest<DefaultConfig>;
using Planner = BasicPlanner<DefaultConfig>;

}  // namespace itp::planner
