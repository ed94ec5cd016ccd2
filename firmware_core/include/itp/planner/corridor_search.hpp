#pragma once
// Decision (paper 1.1) and path QP (1.2) for one iteration step, in rounds.
// A moving obstacle is not a wall: when it blocks the best corridor, leaves
// no decision, or no path QP fits the corridors it shapes, it is left to the
// ST graph (follow or yield) and the stage runs again, one obstacle more per
// round. The path QP tries the decisions in rank order (decision_choice.hpp;
// the coarse QP only sees samples every few metres), each with the curvature
// bound at the expected speed, then at the slowest reachable speed, then
// (the two best only) with the evasive lateral acceleration.
//
// Per-cycle budgets bound the worst case: kMaxDecisionRunsPerCycle decision
// stage runs and kMaxPathSolvesPerCycle path QPs over all iterations and
// rounds; a corridor whose path QP failed is remembered for the cycle and not
// tried again. The coarse and path QPs also charge the cycle's QP work
// (core/work_ledger.hpp), which they share with the speed QPs. A spent
// budget ends the search with a fallback reason.
#include <array>
#include <cstdint>

#include "itp/core/static_vector.hpp"
#include "itp/core/tick_source.hpp"
#include "itp/core/work_ledger.hpp"
#include "itp/decision/decision_stage.hpp"
#include "itp/path/path_optimizer.hpp"
#include "itp/planner/curvature_bounds.hpp"
#include "itp/planner/cycle_inputs.hpp"
#include "itp/planner/decision_choice.hpp"
#include "itp/planner/plan.hpp"
#include "itp/planner/sl_scene.hpp"

namespace itp::planner {

template <class Cfg>
class BasicCorridorSearch {
 public:
  using DecisionStage = decision::BasicDecisionStage<Cfg>;
  using Decision = decision::BasicDecision<Cfg>;
  using PathOptimizer = path::BasicPathOptimizer<Cfg>;
  using PathResult = path::BasicPathResult<Cfg>;
  using StSamples = std::array<Scalar, Cfg::kStSamples>;
  using QpArenas = qp::PlannerQpArenas<Cfg>;

  // The coarse and path QPs' storage (the planner's, docs/memory.md "QP arena").
  explicit BasicCorridorSearch(QpArenas& arenas) : stage_(arenas.coarse()), path_opt_(arenas.path()) {}

  // What a search reads besides the guessed motion.
  struct Context {
    const BasicCycleInputs<Cfg>* inputs = nullptr;
    const BasicCurvatureBounds<Cfg>* bounds = nullptr;
    const PlannerSettings* settings = nullptr;
    PreviousSides previous{};
    TickSource ticks{};
    WorkLedger* work = nullptr;  // the cycle's QP work budget (coarse and path QPs charge it)
  };

  void set_observer(const qp::BasicPlannerQpObserver<Cfg>* observer) {
    stage_.set_observer(observer);
    path_opt_.set_observer(observer);
  }
  // Forget the QPs' hotstart state (a new scene).
  void reset() {
    stage_.reset();
    path_opt_.reset();
  }
  // A new cycle: budgets and remembered corridors start afresh.
  void begin_cycle();

  // The decision and the path for the ego driving `s_guess`. kNone: path
  // holds the chosen corridor's path; else why none was found.
  FallbackReason run(const StSamples& s_guess, BasicSlScene<Cfg>& sl, const Context& ctx,
                     PathResult& path, BasicPlan<Cfg>& out);

  const DecisionStage& stage() const { return stage_; }
  const PathOptimizer& path_optimizer() const { return path_opt_; }
  int chosen() const { return chosen_; }  // index in stage().decisions().kept; -1: none
  const Decision& chosen_decision() const {
    return stage_.decisions().kept[static_cast<std::size_t>(chosen_)];
  }
  bool evasive() const { return evasive_; }  // the chosen path needs the evasive lateral acceleration
  // End of the slice that begins where a blocked corridor ends (`reach`).
  Scalar blocking_slice_end(Scalar reach) const;

 private:
  // The path QPs of one round, in rank order; true when one succeeded.
  bool try_paths(BasicSlScene<Cfg>& sl, const Context& ctx, PathResult& path, BasicPlan<Cfg>& out);
  std::uint64_t corridor_signature(const Decision& d, const path::BasicPathInput<Cfg>& pi) const;
  bool known_infeasible(std::uint64_t corridor) const;

  DecisionStage stage_;
  PathOptimizer path_opt_;
  // Corridors whose path QP failed this cycle (skipped when met again).
  StaticVector<std::uint64_t, Cfg::kRememberedInfeasibleCorridors> infeasible_;
  // Work this cycle, against the per-cycle budgets (itp/config.hpp).
  int path_solves_ = 0;        // path QPs (<= kMaxPathSolvesPerCycle)
  int path_iterations_ = 0;    // their iterations (<= kMaxPathIterationsPerCycle)
  int decision_runs_ = 0;      // decision-stage runs (<= kMaxDecisionRunsPerCycle)
  int tree_nodes_ = 0;         // (<= kMaxTreeNodesPerCycle)
  int coarse_qps_ = 0;         // (<= kMaxCoarseQpsPerCycle)
  int coarse_iterations_ = 0;  // (<= kMaxCoarseIterationsPerCycle)
  bool path_budget_out_ = false;  // a path budget stopped the path QPs of a round
  bool decision_budget_spent() const {
    return decision_runs_ >= Cfg::kMaxDecisionRunsPerCycle || tree_nodes_ >= Cfg::kMaxTreeNodesPerCycle ||
           coarse_qps_ >= Cfg::kMaxCoarseQpsPerCycle || coarse_iterations_ >= Cfg::kMaxCoarseIterationsPerCycle;
  }
  // Path-QP iterations the next solve may take (0: a budget is spent).
  int path_iterations_left(const WorkLedger* work) const {
    const int left = path_solves_ >= Cfg::kMaxPathSolvesPerCycle ? 0 : Cfg::kMaxPathIterationsPerCycle - path_iterations_;
    return work != nullptr ? work->grant(Cfg::kPathSolveSetupWork, Cfg::kPathIterationWork, left) : left;
  }
  int chosen_ = -1;
  bool evasive_ = false;
};

}  // namespace itp::planner
