#pragma once
// One QP of a planner stage (coarse, path, speed): the problem, the solver's
// workspace and result, its settings, and whether the next solve may
// hotstart. A stage's H and A depend only on a few values (its weights, the
// block length, the bumper reaches): its matrix key. The stage rewrites only
// g and the bounds when the key equals the last build's, and the solve
// hotstarts from the held factor exactly then. Keys compare with a defaulted
// operator==, so a field added to a key (a new weight) takes part at once:
// the hotstart can never run on a stale H.
#include "itp/qp/solver.hpp"

namespace itp::qp {

template <class Dims, class Key>
class StageQp {
 public:
  using Scalar = typename Dims::Scalar;

  explicit StageQp(QpSettings<Scalar> settings = {}) : settings_(settings) {}

  // H and A of a problem built for `key` equal the last build's: the stage
  // may keep them and write g and the bounds only.
  bool same_matrices(const Key& key) const { return built_ && key == key_; }

  QpProblem<Dims>& problem() { return problem_; }
  const QpProblem<Dims>& problem() const { return problem_; }
  const QpResult<Dims>& result() const { return result_; }

  // Solves the problem built for `key`: hot from the held factor when the
  // matrices are the same, else cold. After a solve that ended infeasible, at
  // the iteration cap or in numerical trouble the factor of H is still
  // valid, and with `keep_factor_after_failure` the next solve hotstarts from
  // its working set.
  // `max_iterations` > 0 lowers the settings' run-time iteration cap for this
  // solve (what is left of a per-cycle budget).
  QpStatus solve(const Key& key, bool keep_factor_after_failure = false, int max_iterations = 0) {
    QpSettings<Scalar> settings = settings_;
    if (max_iterations > 0 && (settings.max_iterations <= 0 || max_iterations < settings.max_iterations)) {
      settings.max_iterations = max_iterations;
    }
    QpStatus st = QpStatus::kNotFactored;
    if (same_matrices(key) && have_factor_) {
      st = solve_hot(problem_, workspace_, settings, result_);
    }
    if (st == QpStatus::kNotFactored) {
      st = solve_cold(problem_, workspace_, settings, result_);
    }
    have_factor_ = is_usable(st) ||
                   (keep_factor_after_failure && (st == QpStatus::kInfeasible || st == QpStatus::kIterationLimit ||
                                                  st == QpStatus::kNumericalTrouble));
    key_ = key;
    built_ = true;
    return st;
  }

  // Forget the factor: the next solve is cold (a new scene).
  void reset() { have_factor_ = false; }

 private:
  QpProblem<Dims> problem_{};
  QpWorkspace<Dims> workspace_{};
  QpResult<Dims> result_{};
  QpSettings<Scalar> settings_{};
  Key key_{};
  bool built_ = false;
  bool have_factor_ = false;
};

}  // namespace itp::qp
