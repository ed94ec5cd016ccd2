#pragma once
// Paper 1.3: the speed QP. s(t) over the speed horizon is a C2 spline of
// Cfg::kSpeedBlocks quintic blocks with (s, ṡ, s̈) at the knots (the link
// constraints (12) hold by construction; H banded, half-bandwidth 5).
//
// Cost (11), integrated exactly per block:
//   w0 ∫(s - s_up)² + w1 ∫(ṡ - ṡ_expect)² + w2 ∫s̈² + w3 ∫s⃛²
// Constraints: start (13) = init_st; at every sample (0.1 s) rows
//   s_lo <= s <= s_hi     (obstacle decisions (15)-(17), stop lines)
//   v_lo <= ṡ <= v_hi     (speed limit incl. lateral acceleration on the path,
//                          follow/overtake speed conditions)
//   a_min <= s̈ <= a_max   (the dynamic constraints (14), continuous-time form)
// The ST stage (st_graph.hpp) fills the bounds and references.
#include <array>

#include "itp/config.hpp"
#include "itp/qp/planner_observer.hpp"
#include "itp/qp/qp.hpp"
#include "itp/qp/stage_qp.hpp"

namespace itp::speed {

struct SpeedWeights {
  Scalar s_up = Scalar(0.05);   // w0 [1/(m^2 s)]
  Scalar v = Scalar(1);         // w1
  Scalar a = Scalar(2);         // w2
  Scalar jerk = Scalar(1);      // w3
  bool operator==(const SpeedWeights&) const = default;
};

// What the speed QP's H and A depend on (qp::StageQp hotstarts when it is unchanged).
struct SpeedMatrixKey {
  Scalar h = 0;  // [s] block length
  SpeedWeights weights{};
  bool operator==(const SpeedMatrixKey&) const = default;
};

// Per-sample bounds and references at t_k = k * horizon / Cfg::kSpeedSamples
// (k = 0..kSpeedSamples; the last one is the final knot).
template <class Cfg>
struct BasicSpeedBounds {
  std::array<Scalar, Cfg::kStSamples> s_lo{};  // [m] along the path
  std::array<Scalar, Cfg::kStSamples> s_hi{};
  std::array<Scalar, Cfg::kStSamples> v_lo{};  // [m/s]
  std::array<Scalar, Cfg::kStSamples> v_hi{};
  std::array<Scalar, Cfg::kStSamples> s_ref{};  // [m] s_up(t)
  std::array<Scalar, Cfg::kStSamples> v_ref{};  // [m/s] ṡ_expect(t)
  // [m/s²] the braking the plan may use (< 0): comfortable when that keeps
  // every bound, else as hard as the bounds need, at most the vehicle's limit.
  Scalar a_min = Scalar(-3);
};

template <class Cfg>
struct BasicSpeedInput {
  Scalar v0 = 0;   // [m/s]  init_st: speed
  Scalar a0 = 0;   // [m/s²] init_st: acceleration
  Scalar horizon = Cfg::kSpeedHorizon;  // [s]
  Scalar a_min = Scalar(-4);  // [m/s²]
  Scalar a_max = Scalar(2);   // [m/s²]
};

template <class Cfg>
struct BasicSpeedResult {
  qp::QpStatus status = qp::QpStatus::kInvalidInput;
  int iterations = 0;
  Scalar h = 0;  // [s] block length
  std::array<Scalar, 3 * Cfg::kSpeedKnots> knots{};          // (s, ṡ, s̈) per knot
  std::array<Scalar, 6 * Cfg::kSpeedBlocks> coefficients{};  // monomial coefficients per block

  // d^k s / dt^k at t (k = 0..3), clamped to the horizon.
  Scalar eval(Scalar t, int derivative) const;
};

template <class Cfg>
class BasicSpeedOptimizer {
 public:
  using SpeedDims = qp::SpeedQpDims<Scalar, Cfg>;
  using SpeedInput = BasicSpeedInput<Cfg>;
  using SpeedBounds = BasicSpeedBounds<Cfg>;
  using SpeedResult = BasicSpeedResult<Cfg>;
  using QpArena = typename qp::PlannerQpArenas<Cfg>::SpeedArena;

  // The QP's storage (shared with the planner's other QPs or its own).
  explicit BasicSpeedOptimizer(QpArena& arena)
      : qp_(arena, qp::QpSettings<Scalar>{.max_iterations = Cfg::kSpeedQpMaxIterations}) {}

  // Forget the factorisation: the next solve is cold.
  void reset() { qp_.reset(); }
  void set_observer(const qp::BasicPlannerQpObserver<Cfg>* observer) { observer_ = observer; }
  // max_iterations: the run-time iteration cap (<= 0: kSpeedQpMaxIterations).
  void solve(const SpeedInput& in, const SpeedBounds& bounds, const SpeedWeights& w,
             SpeedResult& out, int max_iterations = 0);
  const qp::QpProblem<SpeedDims>& problem() const { return qp_.problem(); }

 private:
  // same_matrices: h and the weights are the last build's (H and A kept).
  void build(const SpeedInput& in, const SpeedBounds& bounds, const SpeedWeights& w, Scalar h,
             bool same_matrices);

  qp::StageQp<SpeedDims, SpeedMatrixKey, QpArena> qp_;
  const qp::BasicPlannerQpObserver<Cfg>* observer_ = nullptr;
};

using SpeedBounds = BasicSpeedBounds<DefaultConfig>;
using SpeedInput = BasicSpeedInput<DefaultConfig>;
using SpeedResult = BasicSpeedResult<DefaultConfig>;
using SpeedOptimizer = BasicSpeedOptimizer<DefaultConfig>;

}  // namespace itp::speed
