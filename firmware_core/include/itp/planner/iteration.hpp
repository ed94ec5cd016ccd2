#pragma once
// The iteration of paper 2: step 0 guesses the ego's motion (the reference
// speed profile, the previous plan's when stitched, or a first speed plan in
// the ego's lane); each step places the moving obstacles where that motion
// meets them, searches a corridor and its path (corridor_search.hpp), plans
// the speed along the path (ST graph and speed QP, paper 1.3), samples the
// trajectory and checks it with the real footprints (collision_check.hpp).
// It stops when the trajectory is collision-free and changed less than the
// thresholds from the step before (or alternates between two results), and
// after Cfg::kMaxPlannerIterations steps in any case.
#include <array>

#include "itp/core/tick_source.hpp"
#include "itp/core/work_ledger.hpp"
#include "itp/geometry/reference_line.hpp"
#include "itp/planner/collision_check.hpp"
#include "itp/planner/corridor_search.hpp"
#include "itp/planner/cycle_inputs.hpp"
#include "itp/planner/plan.hpp"
#include "itp/planner/sl_scene.hpp"
#include "itp/speed/speed_optimizer.hpp"
#include "itp/speed/st_graph.hpp"

namespace itp::planner {

template <class Cfg>
class BasicIteration {
 public:
  using Scene = scene::BasicScene<Cfg>;
  using ReferenceLine = geometry::BasicReferenceLine<Cfg>;
  using Search = BasicCorridorSearch<Cfg>;
  using PathResult = path::BasicPathResult<Cfg>;
  using SpeedResult = speed::BasicSpeedResult<Cfg>;
  using SpeedBounds = speed::BasicSpeedBounds<Cfg>;
  using StGraph = speed::BasicStGraph<Cfg>;
  using SpeedOptimizer = speed::BasicSpeedOptimizer<Cfg>;
  using StSamples = std::array<Scalar, Cfg::kStSamples>;

  // Everything one cycle's iteration reads.
  struct Context {
    const Scene* scene = nullptr;
    const ReferenceLine* reference = nullptr;
    BasicSlScene<Cfg>* sl = nullptr;
    BasicCurvatureBounds<Cfg>* bounds = nullptr;
    BasicCycleInputs<Cfg> inputs;
    decision::MotionLimits limits;  // the envelope planned in (comfort acceleration, hard braking)
    Scalar map_end = 0;             // [m] path s where the reference line ends
    const PlannerSettings* settings = nullptr;
    PreviousSides previous{};  // last plan's sides (hysteresis)
    bool first_cycle = false;  // no ok plan since the last reset: step 0 plans a speed in lane
    TickSource ticks{};
  };

  void set_observer(const qp::BasicPlannerQpObserver<Cfg>* observer) {
    search_.set_observer(observer);
    speed_opt_.set_observer(observer);
  }
  void reset() {
    search_.reset();
    speed_opt_.reset();
  }
  void begin_cycle() {
    search_.begin_cycle();
    speed_budget_out_ = false;
    qp_work_.begin(Cfg::kQpWorkPerCycle);
  }

  // Runs the iteration from `start`. kNone: `out` holds the trajectory with
  // status ok, or fallback evasive / blocked (an optimised trajectory that
  // needs the evasive lateral acceleration, or stops before static
  // obstacles). Any other reason: no usable trajectory, the caller stops safely.
  FallbackReason run(Context& ctx, const StartState& start, BasicPlan<Cfg>& out);

  // The last step's path and speed (the plan's, after an ok cycle).
  const PathResult& path() const { return path_; }
  const SpeedResult& speed() const { return speed_; }
  // Last cycle's path re-expressed in a frame whose s = 0 lies `ds` further on.
  void shift_path_frame(Scalar ds) { path_.s0 += ds; }

  // The QP storage, for the planner's other uses of shared storage between
  // QP solves (planner.hpp: the reference spline's workspace, lending).
  qp::PlannerQpArenas<Cfg>& qp_arenas() { return qp_arenas_; }
  const qp::PlannerQpArenas<Cfg>& qp_arenas() const { return qp_arenas_; }

  const Search& search() const { return search_; }
  const StGraph& st_graph() const { return st_; }
  const SpeedOptimizer& speed_optimizer() const { return speed_opt_; }
  const SpeedBounds& speed_bounds() const { return bounds_; }

 private:
  void guess_first_speed(Context& ctx, const StartState& start, StSamples& s_guess, StSamples& v_guess,
                         BasicPlan<Cfg>& out);
  void plan_speed(Context& ctx, const StSamples& s_guess, const StSamples& v_guess, BasicPlan<Cfg>& out);
  // Speed-QP iterations the next solve may take within the cycle's speed
  // budgets and QP work; 0 (speed_ not usable, speed_budget_out_ set): spent.
  int speed_qp_room(const BasicPlan<Cfg>& out);
  // One speed QP within them (else speed_ is not usable and speed_budget_out_ is set).
  void solve_speed(Context& ctx, BasicPlan<Cfg>& out);
  void sample_trajectory(const ReferenceLine& reference, const StartState& start, BasicPlan<Cfg>& out) const;
  // The room the ego's front keeps before a blocked corridor's end [m].
  Scalar blocked_stop_room(const Context& ctx, const StartState& start, const decision::BasicDecision<Cfg>& chosen,
                           Scalar width) const;

  // The coarse, path and speed QPs' problems and workspaces: one shared
  // storage or one each, as Cfg::kShareQpStorage says (qp/qp_arena.hpp;
  // declared first: the stages below hold them).
  qp::PlannerQpArenas<Cfg> qp_arenas_{};
  Search search_{qp_arenas_};
  PathResult path_{};
  StGraph st_{};
  SpeedBounds bounds_{};
  SpeedOptimizer speed_opt_{qp_arenas_.speed()};
  SpeedResult speed_{};
  bool speed_budget_out_ = false;  // a speed budget (itp/config.hpp) ran out this cycle
  WorkLedger qp_work_{};           // the cycle's QP work: coarse, path and speed QPs
};

}  // namespace itp::planner
