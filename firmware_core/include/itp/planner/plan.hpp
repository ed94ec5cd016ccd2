#pragma once
// What the planner returns for one cycle (plan/1): the trajectory sampled
// every 0.1 s over the speed horizon, the status (ok, fallback with a reason,
// invalid input with the validation reason), the decisions per obstacle, the
// iteration count and per-stage timing from the port's counter.
#include <cstdint>

#include "itp/config.hpp"
#include "itp/core/static_vector.hpp"
#include "itp/core/status.hpp"
#include "itp/scene/validation.hpp"
#include "itp/speed/st_graph.hpp"

namespace itp::planner {

struct TrajectoryPoint {
  Scalar t = 0;        // [s] from the planning time
  Scalar x = 0;        // [m] rear-axle centre
  Scalar y = 0;        // [m]
  Scalar heading = 0;  // [rad]
  Scalar kappa = 0;    // [1/m]
  Scalar v = 0;        // [m/s]
  Scalar a = 0;        // [m/s^2]
  Scalar s = 0;        // [m] along the reference line
  Scalar l = 0;        // [m] lateral offset from it
};

enum class FallbackReason : std::uint8_t {
  kNone = 0,
  kNoDecision,        // no corridor for the ego, or no coarse QP solvable
  kBlocked,           // every lane blocked by static obstacles: stop before them
  kPathQpFailed,
  kSpeedQpFailed,
  kCollision,         // the optimised trajectory still collides after the last iteration
  kHorizonTooShort,   // the ego is at (or past) the end of the reference line
  kEvasive,           // the only path found needs more than lat_acc_max (up to evasive_lat_acc)
  kBudget,            // a per-cycle work budget ran out (the worst-case bound, itp/config.hpp)
};

const char* to_string(FallbackReason reason);

enum class LateralSide : std::uint8_t { kNone = 0, kLeft, kRight };

struct ObstacleDecision {
  std::int32_t obstacle = 0;
  LateralSide lateral = LateralSide::kNone;                       // path passes it on this side
  speed::Longitudinal longitudinal = speed::Longitudinal::kIgnore;  // from the ST graph
  bool dynamic = false;
};

// Per-stage time in the port's counter ticks (0 when no tick source is set).
struct StageTiming {
  std::uint64_t prepare = 0;   // validation, reference line, SL projection
  std::uint64_t decision = 0;  // zones, tree, coarse QPs (all iterations)
  std::uint64_t path = 0;      // path QPs
  std::uint64_t speed = 0;     // ST graph and speed QPs
  std::uint64_t check = 0;     // trajectory sampling and collision checks
  std::uint64_t total = 0;
  std::uint64_t tick_hz = 0;
  int decision_runs = 0;       // decision-stage calls (iterations x dynamic re-decisions)
  // The work of the cycle in the units of its budgets (itp/config.hpp; the
  // worst-case table, `make wcet`, divides the stage ticks by them).
  std::uint64_t coarse = 0;    // coarse QPs (part of `decision`)
  int tree_nodes = 0;          // decision-tree nodes expanded
  int coarse_qps = 0;
  int coarse_iterations = 0;
  int path_solves = 0;
  int path_iterations = 0;
  int speed_solves = 0;        // speed QPs (each after at most one ST graph build)
  int speed_iterations = 0;
};

// The output of one cycle, with the capacities of configuration Cfg.
template <class Cfg>
struct BasicPlan {
  PlanStatus status = PlanStatus::kFallback;
  FallbackReason fallback = FallbackReason::kNone;
  scene::ValidationReason invalid = scene::ValidationReason::kNone;
  int iterations = 0;
  StaticVector<TrajectoryPoint, Cfg::kTrajectorySamples> trajectory;
  StaticVector<ObstacleDecision, Cfg::kMaxObstacles> decisions;
  StageTiming timing;
  // Counts for reports: QP solves and their active-set iterations this cycle.
  int qp_solves = 0;
  int qp_iterations = 0;
  // FallbackReason::kCollision: the obstacle the last optimised trajectory
  // met first, and when (plan time); -1 / < 0 otherwise.
  std::int32_t collision_obstacle = -1;
  Scalar collision_time = -1;  // [s]
};

using Plan = BasicPlan<DefaultConfig>;

}  // namespace itp::planner
