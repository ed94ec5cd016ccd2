#pragma once
// Paper 1.1, coarse evaluation of one decision (eq. 2-4). The corridor is
// sampled at kCoarseSamples points in s; the small QP
//   min Σ w_ls (l_{i-1} + l_{i+1} - 2 l_i)² + Σ w_lr (l_i - l_ref)²
//     + Σ w_ts (t_{i-1} + t_{i+1} - 2 t_i)² + Σ w_tl (t_i - t_lb,i)²
//   s.t. l_0 = l_init, t_0 = t_init, l_lb,i <= l_i <= l_ub,i, t_i >= t_lb,i,
//        t_{i+1} - t_i >= Δs / v_limit
// gives a coarse path and timing, from which curvature, speed, longitudinal
// and lateral acceleration follow; the decision cost is eq. (4).
#include <cstdint>

#include "itp/config.hpp"
#include "itp/decision/convex_space.hpp"
#include "itp/decision/curvature_profile.hpp"
#include "itp/decision/decision_tree.hpp"
#include "itp/decision/motion_limits.hpp"
#include "itp/qp/planner_observer.hpp"
#include "itp/qp/qp.hpp"
#include "itp/qp/stage_qp.hpp"

namespace itp::decision {

// Eq. (2), the coarse QP: its H depends on these alone (qp::StageQp's key).
struct CoarseQpWeights {
  Scalar l_smooth = Scalar(10);   // second difference of l   [1/m^2]
  Scalar l_ref = Scalar(0.05);    // deviation from l_ref     [1/m^2]
  Scalar t_smooth = Scalar(10);   // second difference of t   [1/s^2]
  Scalar t_lb = Scalar(1);        // lateness versus t_lb     [1/s^2]
  bool operator==(const CoarseQpWeights&) const = default;
};

struct CoarseWeights {
  CoarseQpWeights qp{};
  // Eq. (4), PathCost and DynamicCost, one weight per term.
  Scalar kappa_mean = Scalar(10);     // w11 x mean |κ|      [m]
  Scalar kappa_var = Scalar(100);     // w12 x var κ         [m^2]
  Scalar a_lat_mean = Scalar(0.5);    // w21 x mean |a_lat|  [s^2/m]
  Scalar a_lat_var = Scalar(0.1);     // w22 x var a_lat
  Scalar a_lon_mean = Scalar(0.5);    // w23 x mean |a_lon|
  Scalar a_lon_var = Scalar(0.1);     // w24 x var a_lon
};

template <class Cfg>
struct BasicCoarseInput {
  Scalar l_init = 0;       // [m] ego's l (or the stitched plan's)
  Scalar v_init = 0;       // [m/s] ego's speed
  Scalar l_ref = 0;        // [m] target lane centre
  Scalar vehicle_width = Scalar(1.9);     // [m]
  Scalar lateral_margin = Scalar(0.2);    // [m] kept from zone edges, each side
  Scalar stop_margin = Scalar(3.0);       // [m] distance kept before a blocked corridor's end
  MotionLimits limits;
  const BasicCurvatureProfile<Cfg>* kappa_ref = nullptr;  // κ_ref(s); null = straight road
};

// What the decision stage keeps of each evaluated decision: its status, the
// terms of eq. (4), and where its coarse path ends (the ranking reads l_end).
struct CoarseScore {
  qp::QpStatus status = qp::QpStatus::kInvalidInput;
  int samples = 0;
  Scalar l_end = 0;                       // [m] l at the last sample (when usable)
  Scalar kappa_mean = 0, kappa_var = 0;   // |κ| mean [1/m], variance [1/m^2]
  Scalar a_lat_mean = 0, a_lat_var = 0;   // [m/s^2], [m^2/s^4]
  Scalar a_lon_mean = 0, a_lon_var = 0;
  Scalar path_cost = 0;      // w11 μ|κ| + w12 σ²κ
  Scalar dynamic_cost = 0;   // w21..w24 terms
  Scalar decision_cost = 0;  // geometric cost + path cost + dynamic cost (eq. 4)
  int qp_iterations = 0;
};

// One evaluation in full: the score and the coarse samples it came from.
template <class Cfg>
struct BasicCoarseResult : CoarseScore {
  Scalar ds = 0;                                    // [m] sample spacing
  std::array<Scalar, Cfg::kCoarseSamples> s{};      // [m]
  std::array<Scalar, Cfg::kCoarseSamples> l{};      // [m]
  std::array<Scalar, Cfg::kCoarseSamples> t{};      // [s]
  std::array<Scalar, Cfg::kCoarseSamples> l_lb{}, l_ub{};  // [m] corridor at the samples
  std::array<Scalar, Cfg::kCoarseSamples> t_lb{};          // [s]
};

// Evaluates decisions with the coarse QP, whose solver workspace is the arena
// shared with the planner's other QPs; one instance serves every decision of
// a cycle.
template <class Cfg>
class BasicCoarseEvaluator {
 public:
  using CoarseInput = BasicCoarseInput<Cfg>;
  using CoarseResult = BasicCoarseResult<Cfg>;
  using ConvexSpace = BasicConvexSpace<Cfg>;
  using Decision = BasicDecision<Cfg>;
  using QpArena = typename qp::PlannerQpArenas<Cfg>::CoarseArena;

  explicit BasicCoarseEvaluator(QpArena& arena)
      : qp_(arena, qp::QpSettings<Scalar>{.max_iterations = Cfg::kCoarseQpMaxIterations}) {}

  // Forget the factorisation: the next solve is cold.
  void reset() { qp_.reset(); }
  void set_observer(const qp::BasicPlannerQpObserver<Cfg>* observer) { observer_ = observer; }
  // max_iterations: the coarse QP's run-time iteration cap (<= 0: kCoarseQpMaxIterations).
  void evaluate(const ConvexSpace& space, const Decision& decision, const CoarseInput& in,
                const CoarseWeights& w, CoarseResult& out, int max_iterations = 0);

 private:
  static constexpr int kN = Cfg::kCoarseSamples;
  bool sample_corridor(const ConvexSpace& space, const Decision& decision, const CoarseInput& in,
                       CoarseResult& out) const;
  void build_qp(const CoarseInput& in, const CoarseWeights& w, const CoarseResult& out);
  void score(const Decision& decision, const CoarseInput& in, const CoarseWeights& w,
             CoarseResult& out) const;

  using CoarseDims = qp::CoarseQpDims<Scalar, Cfg>;
  // H depends only on the QP weights: while they stay the same, every solve
  // after the first restarts from the last (new g and bounds, same H).
  qp::StageQp<CoarseDims, CoarseQpWeights, QpArena> qp_;
  const qp::BasicPlannerQpObserver<Cfg>* observer_ = nullptr;
};

// Earliest arrival times t_lb at `count` samples s_0 + i Δs from a forward /
// backward kinematic pass: speed limit, lateral acceleration on κ_ref,
// acceleration and braking limits; `stop_at_end` brings the speed to zero at
// the last sample (a blocked corridor).
template <class Cfg>
void earliest_arrival(const BasicCoarseInput<Cfg>& in, Scalar s0, Scalar ds, int count,
                      bool stop_at_end, Scalar* t_lb);

using CoarseInput = BasicCoarseInput<DefaultConfig>;
using CoarseResult = BasicCoarseResult<DefaultConfig>;
using CoarseEvaluator = BasicCoarseEvaluator<DefaultConfig>;

}  // namespace itp::decision
