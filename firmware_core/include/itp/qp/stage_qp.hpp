#pragma once
// One QP of a planner stage (coarse, path, speed): the problem, the result,
// its settings, and whether the next solve may restart from the last one. A
// stage's H and A depend only on a few values (its weights, the block length,
// the bumper reaches): its matrix key. The stage rewrites only g and the
// bounds when the key equals the last build's. Keys compare with a defaulted
// operator==, so a field added to a key (a new weight) takes part at once: a
// restart can never run on a stale H.
//
// The solver's workspace lives in an arena shared with the other stages
// (workspace_arena.hpp). With the same matrices, the next solve hotstarts
// from the held factor while no other stage has claimed the arena since;
// otherwise it restarts warm: H factored again and the last working set
// loaded (the same start as a hotstart, so the same iterations; the loading
// costs one row append per entry, docs/memory.md "QP arena").
#include "itp/qp/solver.hpp"
#include "itp/qp/workspace_arena.hpp"

namespace itp::qp {

template <class Dims, class Key, class Arena>
class StageQp {
 public:
  using Scalar = typename Dims::Scalar;

  explicit StageQp(Arena& arena, QpSettings<Scalar> settings = {}) : arena_(arena), settings_(settings) {}
  StageQp(const StageQp&) = delete;
  StageQp& operator=(const StageQp&) = delete;

  // H and A of a problem built for `key` equal the last build's: the stage
  // may keep them and write g and the bounds only.
  bool same_matrices(const Key& key) const { return built_ && key == key_; }

  QpProblem<Dims>& problem() { return problem_; }
  const QpProblem<Dims>& problem() const { return problem_; }
  const QpResult<Dims>& result() const { return result_; }

  // Solves the problem built for `key`: with the same matrices, hot from the
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
    const bool restart = same_matrices(key) && have_start_;
    bool fresh = false;
    QpWorkspace<Dims>& ws = arena_.template claim<Dims>(this, fresh);
    QpStatus st = QpStatus::kNotFactored;
    if (restart && !fresh) {
      st = solve_hot(problem_, ws, settings, result_);
    } else if (restart) {
      const WorkingSet<Dims> start = result_.working_set;  // the solve overwrites result_
      st = solve_warm(problem_, ws, settings, start, result_);
    }
    if (st == QpStatus::kNotFactored) {
      st = solve_cold(problem_, ws, settings, result_);
    }
    have_start_ = is_usable(st) ||
                  (keep_factor_after_failure && (st == QpStatus::kInfeasible || st == QpStatus::kIterationLimit ||
                                                 st == QpStatus::kNumericalTrouble));
    key_ = key;
    built_ = true;
    return st;
  }

  // Forget the start: the next solve is cold (a new scene).
  void reset() { have_start_ = false; }

 private:
  Arena& arena_;
  QpProblem<Dims> problem_{};
  QpResult<Dims> result_{};
  QpSettings<Scalar> settings_{};
  Key key_{};
  bool built_ = false;
  bool have_start_ = false;  // the held factor (hot) or result_.working_set (warm) is a valid start
};

}  // namespace itp::qp
