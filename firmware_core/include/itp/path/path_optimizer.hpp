#pragma once
// Paper 1.2: the path QP. l(s) over the SL horizon is a C2 spline of
// Cfg::kPathBlocks quintic blocks; the variables are (l, l', l'') at the
// Cfg::kPathBlocks + 1 knots (quintic Hermite parameterisation: the link
// constraints (7) hold by construction and H is banded, half-bandwidth 5).
//
// Cost (6), integrated exactly per block:
//   w0 ∫(l - l_target)² + w1 ∫l'² + w2 ∫l''² + w3 ∫l'''² + w_obs ∫(l - l_mid(s))²
// with l_mid the middle of the chosen corridor (piecewise constant in s; in a
// zone that no obstacle bounds, the target lane centre clamped into it).
// Constraints: start (l, l', l'') = init_sl; at Cfg::kPathSamplesPerBlock samples
// per block the corridor (8) l_lo + w/2 <= l + β l' <= l_hi - w/2, and
// bounds on l' and on l'' (curvature limit minus κ_ref).
#include <array>

#include "itp/config.hpp"
#include "itp/decision/convex_space.hpp"
#include "itp/decision/curvature_profile.hpp"
#include "itp/decision/decision_tree.hpp"
#include "itp/qp/planner_observer.hpp"
#include "itp/qp/qp.hpp"
#include "itp/qp/stage_qp.hpp"

namespace itp::path {

struct PathWeights {
  Scalar target = Scalar(0.02);   // w0   [1/m^3]
  Scalar d1 = Scalar(1);          // w1   [1/m]
  Scalar d2 = Scalar(100);        // w2   [m]
  Scalar d3 = Scalar(2000);       // w3   [m^3]
  Scalar obstacle = Scalar(0.1);  // w_obs [1/m^3]
  bool operator==(const PathWeights&) const = default;
};

// What the path QP's H and A depend on (qp::StageQp hotstarts when it is unchanged).
struct PathMatrixKey {
  Scalar h = 0;            // [m] block length
  Scalar front_reach = 0;  // [m] rows of (8)
  Scalar rear_reach = 0;   // [m]
  PathWeights weights{};
  bool operator==(const PathMatrixKey&) const = default;
};

template <class Cfg>
struct BasicPathInput {
  Scalar s0 = 0;       // [m] start of the path (the ego's s)
  Scalar length = Cfg::kPathLength;  // [m]
  Scalar l0 = 0;       // [m]   init_sl: l
  Scalar dl0 = 0;      // [-]   init_sl: dl/ds
  Scalar ddl0 = 0;     // [1/m] init_sl: d²l/ds²
  Scalar l_target = 0;             // [m] target lane centre
  Scalar vehicle_width = Scalar(1.9);   // [m]
  // (8) with the car's real ends instead of the paper's β = 0.2: the rows
  // bound l + front_reach·l' and l − rear_reach·l' (the lateral offsets of the
  // front and rear bumper centres) so that a heading never swings a corner out.
  Scalar front_reach = Scalar(3.8);     // [m] rear axle to front bumper
  Scalar rear_reach = Scalar(1.0);      // [m] rear axle to rear bumper
  Scalar dl_max = Scalar(0.5);          // [-] |l'| bound
  Scalar kappa_max = Scalar(0.2);       // [1/m] curvature limit
  const decision::BasicCurvatureProfile<Cfg>* kappa_ref = nullptr;  // null: straight
  // |κ| allowed along s, e.g. min(κ_max, lat_acc_max / v(s)²) at the expected
  // speed; null: kappa_max everywhere.
  const decision::BasicCurvatureProfile<Cfg>* kappa_bound = nullptr;
};

template <class Cfg>
struct BasicPathResult {
  qp::QpStatus status = qp::QpStatus::kInvalidInput;
  int iterations = 0;
  Scalar s0 = 0;  // [m]
  Scalar h = 0;   // [m] block length
  std::array<Scalar, 3 * Cfg::kPathKnots> knots{};  // (l, l', l'') per knot
  std::array<Scalar, 6 * Cfg::kPathBlocks>
      coefficients{};  // monomial coefficients per block (from knots)

  // d^k l / ds^k at s (k = 0..3), clamped to the horizon.
  Scalar eval(Scalar s, int derivative) const;
};

template <class Cfg>
class BasicPathOptimizer {
 public:
  using PathDims = qp::PathQpDims<Scalar, Cfg>;
  using PathInput = BasicPathInput<Cfg>;
  using PathResult = BasicPathResult<Cfg>;
  using ConvexSpace = decision::BasicConvexSpace<Cfg>;
  using Decision = decision::BasicDecision<Cfg>;
  using QpArena = typename qp::PlannerQpArenas<Cfg>::PathArena;

  // The QP's storage (shared with the planner's other QPs or its own).
  explicit BasicPathOptimizer(QpArena& arena)
      : qp_(arena, qp::QpSettings<Scalar>{.max_iterations = Cfg::kPathQpMaxIterations}) {}

  // Forget the factorisation: the next solve is cold.
  void reset() { qp_.reset(); }
  void set_observer(const qp::BasicPlannerQpObserver<Cfg>* observer) { observer_ = observer; }
  // max_iterations: the run-time iteration cap (<= 0: kPathQpMaxIterations).
  void solve(const ConvexSpace& space, const Decision& decision, const PathInput& in,
             const PathWeights& w, PathResult& out, int max_iterations = 0);
  // The QP of the last solve (for dumps and tests).
  const qp::QpProblem<PathDims>& problem() const { return qp_.problem(); }

 private:
  // same_matrices: h, the reaches and the weights are the last build's (H and A kept).
  void build(const ConvexSpace& space, const Decision& decision, const PathInput& in,
             const PathWeights& w, Scalar h, bool same_matrices);

  // A feasible path QP converges in under 30 iterations (hot) here; proving
  // infeasibility takes 110-130. The cap turns most of those into an early
  // iteration-limit failure at half the cost (same outcome: next decision).
  qp::StageQp<PathDims, PathMatrixKey, QpArena> qp_;
  const qp::BasicPlannerQpObserver<Cfg>* observer_ = nullptr;
};

using PathInput = BasicPathInput<DefaultConfig>;
using PathResult = BasicPathResult<DefaultConfig>;
using PathOptimizer = BasicPathOptimizer<DefaultConfig>;

}  // namespace itp::path
