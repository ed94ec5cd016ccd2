#pragma once
// One QP of a planner stage (coarse, path, speed): its result, its settings,
// and whether the next solve may restart from the last one. A stage's H and
// A depend only on a few values (its weights, the block length, the bumper
// reaches): its matrix key. Keys compare with a defaulted operator==, so a
// field added to a key (a new weight) takes part at once: a restart can never
// run on a stale H.
//
// The problem and the solver's workspace live in an arena (qp_arena.hpp): the
// stage's own, or one shared with the other stages. While a stage holds it, a build for the last
// key writes only g and the bounds, and the solve hotstarts from the held
// factor. After another stage's claim the build writes the whole problem and
// the solve restarts warm: H factored again and the last working set loaded,
// the same start as a hotstart, so the same iterations (docs/memory.md, "QP
// arena").
#include "itp/qp/chain_qp.hpp"
#include "itp/qp/qp_arena.hpp"

namespace itp::qp {

template <class Dims, class Key, class Arena>
class StageQp {
 public:
  using Scalar = typename Dims::Scalar;

  explicit StageQp(Arena& arena, QpSettings<Scalar> settings = {}) : arena_(arena), settings_(settings) {}
  StageQp(const StageQp&) = delete;
  StageQp& operator=(const StageQp&) = delete;

  // The problem in the arena holds H and A for `key`: a build may keep them
  // and write g and the bounds only.
  bool same_matrices(const Key& key) const { return solved_ && key == key_ && arena_.held_by(this); }

  // The problem to write (claims the arena). After another stage's claim it
  // holds sizes 0: same_matrices() was false, the caller builds all of it.
  QpProblem<Dims>& problem() { return claim().problem; }
  // The last solve's problem; valid while no other stage has claimed the
  // arena since (dumps read it right after the solve).
  const QpProblem<Dims>& problem() const { return arena_.template held<Dims>(this).problem; }
  const QpResult<Dims>& result() const { return result_; }

  // Solves the problem built for `key`: for the last solve's key hot from the
  // held factor or warm from the last working set (see above), else cold.
  // After a solve that ended infeasible, at the iteration cap or in numerical
  // trouble, with `keep_factor_after_failure` the next solve restarts from its
  // working set too.
  // `max_iterations` > 0 lowers the settings' run-time iteration cap for this
  // solve (what is left of a per-cycle budget).
  QpStatus solve(const Key& key, bool keep_factor_after_failure = false, int max_iterations = 0) {
    QpSettings<Scalar> settings = settings_;
    if (max_iterations > 0 && (settings.max_iterations <= 0 || max_iterations < settings.max_iterations)) {
      settings.max_iterations = max_iterations;
    }
    const bool restart = solved_ && key == key_ && have_start_;
    QpStorage<Dims>& qp = claim();  // already held since the build
    QpStatus st = QpStatus::kNotFactored;
    if (restart && factor_held_) {
      st = solve_hot(qp.problem, qp.workspace, settings, result_);
    } else if (restart) {
      // A chain-form QP (the coarse QP) goes to the chain solver first
      // (chain_qp.hpp), from the last working set and, the key being the
      // same, on the same H and A; it leaves no factor, so its restarts all
      // come here.
      const WorkingSet<Dims> start = result_.working_set;  // the solve overwrites result_
      st = solve_structured(qp.problem, qp.workspace, settings, &start, result_, true);
    }
    if (st == QpStatus::kNotFactored) {
      st = solve_cold_structured(qp.problem, qp.workspace, settings, result_);
    }
    have_start_ = is_usable(st) ||
                  (keep_factor_after_failure && (st == QpStatus::kInfeasible || st == QpStatus::kIterationLimit ||
                                                 st == QpStatus::kNumericalTrouble));
    factor_held_ = qp.workspace.factored;
    key_ = key;
    solved_ = true;
    return st;
  }

  // Forget the start: the next solve is cold (a new scene).
  void reset() { have_start_ = false; }

 private:
  QpStorage<Dims>& claim() {
    bool fresh = false;
    QpStorage<Dims>& qp = arena_.template claim<Dims>(this, fresh);
    if (fresh) factor_held_ = false;  // the workspace holds another QP's factor
    return qp;
  }

  Arena& arena_;
  QpResult<Dims> result_{};
  QpSettings<Scalar> settings_{};
  Key key_{};                 // of the last solve
  bool solved_ = false;
  bool have_start_ = false;   // result_.working_set (and, if held, the factor) is a valid start
  bool factor_held_ = false;  // the arena's workspace holds this stage's last factor
};

}  // namespace itp::qp
