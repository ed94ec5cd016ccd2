#pragma once
// The one configuration header: every size, capacity and loop bound of the
// planner derives from the constexpr values here. The sizes form a
// configuration type (Configuration<Sizes>, below) that the planner and its
// stages are templated on; the constants in namespace config size nothing
// (validation ranges, reference-line fit, link). Raising a capacity is a
// rebuild, never a run-time allocation.
#include <cstddef>
#include <cstdint>

namespace itp {

#ifdef ITP_SCALAR_FLOAT
using Scalar = float;
#else
using Scalar = double;
#endif

namespace config {

// --- Reference line and Frenet frame (docs/frenet.md) -------------------------
// The smoothing spline is fitted through the polyline plus up to
// kReferenceEndMirror points mirrored at each end, covering at least
// kReferenceMirrorLength (so the natural end condition, kappa = 0, acts far
// from the real ends and does not flatten their curvature).
inline constexpr int kReferenceEndMirror = 16;
inline constexpr Scalar kReferenceMirrorLength = Scalar(15);    // [m] ~7 smoothing bandwidths
inline constexpr Scalar kReferenceSmoothing = Scalar(16);       // [m^3] spline penalty lambda
                                                                // (bandwidth lambda^(1/4) = 2 m)
inline constexpr Scalar kMinReferencePointSpacing = Scalar(0.05);  // [m] closer = repeated point
inline constexpr Scalar kMaxReferenceTurnPerPoint = Scalar(1.0471975511965976);  // [rad] 60 deg
inline constexpr Scalar kMinReferenceLineLength = Scalar(1);    // [m] a map may end just ahead
inline constexpr int kArcLengthNewtonSteps = 4;                 // s -> spline parameter
inline constexpr int kProjectionNewtonSteps = 8;                // point -> foot point
inline constexpr int kMaxBoxEdgeSamples = 16;                   // SL box: points per box edge
inline constexpr Scalar kBoxEdgeSampleSpacing = Scalar(1);      // [m]

// --- Scene validation (docs/scene.md) ----------------------------------------
inline constexpr Scalar kMaxAbsoluteSpeed = Scalar(70);         // [m/s] speed limit and any speed
inline constexpr Scalar kMaxAbsoluteAcceleration = Scalar(20);  // [m/s^2] ego a and limits
inline constexpr Scalar kMaxAbsoluteCurvature = Scalar(1);      // [1/m] ego kappa and limit
inline constexpr Scalar kMinLaneWidth = Scalar(2);              // [m]
inline constexpr Scalar kMaxLaneWidth = Scalar(6);              // [m]
inline constexpr Scalar kMaxBoundaryOffset = Scalar(50);        // [m] |l| of a road boundary
inline constexpr Scalar kMaxObjectSize = Scalar(30);            // [m] box length/width
// Sizes and limits have lower bounds too: a 1e-30 m box or a 1e-30 m/s^2
// braking limit is a corrupted value, not a vehicle.
inline constexpr Scalar kMinObjectSize = Scalar(0.05);          // [m] box length/width, wheelbase
inline constexpr Scalar kMinSpeedLimit = Scalar(1);             // [m/s] road speed limit
inline constexpr Scalar kMinLimitAcceleration = Scalar(0.5);    // [m/s^2] |a_min|, a_max, lat_acc_max
inline constexpr Scalar kMinLimitCurvature = Scalar(0.01);      // [1/m] kappa_max (radius <= 100 m)
// Headings need not be wrapped, but beyond four turns either way a heading
// is no longer an angle anyone meant (and float32 on the link keeps 2e-6 rad
// up to here).
inline constexpr Scalar kMaxAbsoluteHeading = Scalar(25.132741228718345);  // [rad] 8 pi
inline constexpr Scalar kMaxCoordinate = Scalar(1.0e5);         // [m] |x|, |y|
// Scene time: the largest `now` at which Scalar still resolves 1 ms
// (double: 1e9 s, ulp 1.2e-7 s; float: 1e4 s, ulp 1e-3 s). A vehicle that
// runs longer restarts its scene clock (a new session).
inline constexpr Scalar kMaxSceneTime = sizeof(Scalar) >= 8 ? Scalar(1e9) : Scalar(1e4);  // [s]
// Obstacle trajectory samples are judged relative to the scene time: |t - now|
// at most this, so that nothing expires however long the vehicle runs.
inline constexpr Scalar kMaxPredictionTime = Scalar(3600);      // [s] |t - now| of a sample
inline constexpr Scalar kMaxEgoOffsetFromReference = Scalar(10);  // [m] ego to polyline

// --- Serial link -------------------------------------------------------------
// A message travels in segments of at most this many bytes (docs/protocol.md):
// the decoder's buffer holds one segment; message buffers are sized by the
// largest message of the configuration (link/planner_messages.hpp).
inline constexpr std::size_t kMaxSegmentBytes = 1024;
inline constexpr std::size_t kBuildIdBytes = 48;         // fixed field in Pong

}  // namespace config

// --- A planner configuration ----------------------------------------------
// The planner and every stage that owns memory are class templates on a
// configuration type (BasicPlanner<Cfg>, ...). A configuration is
// Configuration<Sizes>: Sizes holds the primary sizes (derive from
// DefaultSizes and override what differs), Configuration adds everything
// that follows from them and checks them, so derived sizes can never
// disagree with the primary ones. The library is compiled for the
// configurations listed in itp/configurations.hpp.
struct DefaultSizes {
  // Planning horizon (paper, Table 1)
  static constexpr Scalar kPathLength = Scalar(100);      // [m] SL horizon (the shortest)
  // The SL horizon grows with speed to cover where the speed horizon can take
  // the ego (v T + front + stop margin), up to this; the speed plan never
  // leaves it (it stops within it instead).
  static constexpr Scalar kMaxPathLength = Scalar(250);   // [m] 7 s at 36 m/s (130 km/h)
  static constexpr Scalar kSpeedHorizon = Scalar(7);      // [s] ST horizon
  static constexpr Scalar kTrajectoryStep = Scalar(0.1);  // [s] output sample step

  // Scene capacities
  static constexpr int kMaxReferencePoints = 128;  // reference-line polyline points
  static constexpr int kMaxBoundaryPoints = 32;    // [s, l] pairs per road boundary
  static constexpr int kMaxStaticObstacles = 10;
  static constexpr int kMaxDynamicObstacles = 5;
  static constexpr int kMaxPredictionSamples = 80;  // poses per dynamic obstacle
  // Convex space: extra slice edges where the road's edges change (a
  // narrowing, a lane that ends), beside the obstacles' edges. Without them a
  // slice free of obstacles takes the narrowest road over its whole length.
  static constexpr int kMaxRoadCuts = 8;

  // Convex space and decision (paper 1.1)
  // The objects that take part in the decision stage, at most (the paper's
  // envelope). A scene that holds more gives them the most relevant ones
  // (planner/sl_scene: the nearest ahead); every object of the scene is still
  // respected by the ST graph and the collision check.
  static constexpr int kDecisionStaticObstacles = 10;
  static constexpr int kDecisionDynamicObstacles = 5;
  static constexpr int kKeptDecisions = 20;  // K best decisions evaluated
  // Decision-tree search: nodes (zone visits) expanded per cycle, at most. The
  // branch-and-bound search stops there and keeps the best K found so far.
  static constexpr int kMaxTreeNodes = 4096;
  static constexpr int kCoarseSamples = 20;  // coarse (l, t) samples per decision

  // Path and speed QPs (paper 1.2, 1.3)
  static constexpr int kPathBlocks = 20;   // quintic SL blocks over kPathLength
  static constexpr int kSpeedBlocks = 14;  // quintic ST blocks over kSpeedHorizon

  // Iteration (paper 2) and the per-cycle budgets that bound the worst case
  static constexpr int kMaxPlannerIterations = 5;
  static constexpr int kRememberedInfeasibleCorridors = 16;  // path QPs not repeated on them
  static constexpr int kMaxPathSolvesPerCycle = 10;          // path QPs (max 16, p99.9 10)
  static constexpr int kPathQpMaxIterations = 60;            // path QP iteration cap
  // Decision-stage runs (convex space, tree, up to kKeptDecisions coarse QPs) per
  // cycle, over all iterations and their rounds (a round leaves one more moving
  // obstacle to the ST graph); without it up to kMaxPlannerIterations x
  // (kMaxDynamicObstacles + 1) = 30. A cycle that needs more falls back (WCET
  // bound); the value's cost in fallbacks: docs/performance.md, "Worst case".
  static constexpr int kMaxDecisionRunsPerCycle = 15;
  // Run-time iteration caps of the other QPs (the compile-time kMaxIterations,
  // 3 (n + m), is 180 for the coarse and 765 for the speed QP: far above need).
  static constexpr int kCoarseQpMaxIterations = 60;   // coarse QP cap (seeds 1-10: no change in outcome)
  static constexpr int kSpeedQpMaxIterations = 120;   // speed QP cap (seeds 1-10: no change in outcome)
  // Per-cycle budgets in the units that bound each stage's cost: the derived
  // worst case is the sum of budget x worst cost per unit (`make wcet`,
  // docs/performance.md "Worst case"). A cycle whose stage runs out of one
  // falls back (FallbackReason::kBudget). Closed-loop use, seeds 1-10 x 24 000
  // cycles without budgets (max, p99.9) beside each; cost in fallbacks +0.27-0.79 %.
  static constexpr int kMaxTreeNodesPerCycle = 512;        // tree nodes in all runs (max 530, p99.9 158)
  static constexpr int kMaxCoarseQpsPerCycle = 32;          // coarse QPs in all runs (max 80, p99.9 24)
  static constexpr int kMaxCoarseIterationsPerCycle = 300;  // their iterations (max 1210, p99.9 292)
  static constexpr int kMaxPathIterationsPerCycle = 270;    // path-QP iterations (max 853, p99.9 379): failed
                                                            // QPs rationed, the largest term of the bound
  static constexpr int kMaxSpeedSolvesPerCycle = 8;         // speed QPs (max 14, p99.9 8)
  static constexpr int kMaxSpeedIterationsPerCycle = 300;   // their iterations (max 498, p99.9 184)
  // One budget for the three QP stages together (core/work_ledger.hpp): each
  // coarse, path and speed QP's setup and each of its iterations costs its
  // worst measured cost on the reference target, in thousands of Cortex-M7
  // instructions (`make wcet-measure`: upper envelope over the default and the
  // stress suite x 1.2, rounded up; `make wcet` fails when a refit exceeds
  // them). A cycle may spend kQpWorkPerCycle of them: the stages' budgets
  // above sum to 41.5 M instructions, this caps their sum at 22 M. Seeds 1-10,
  // fallbacks against no budgets: +0.31..+0.92 % of cycles (the stage budgets
  // alone: +0.27..+0.79 %; docs/performance.md, "Worst case").
  static constexpr int kQpWorkPerCycle = 22000;       // [k instructions]
  static constexpr int kCoarseQpSetupWork = 115;      // per coarse QP
  static constexpr int kCoarseIterationWork = 11;     // per coarse-QP iteration
  static constexpr int kPathSolveSetupWork = 717;     // per path QP (setup, factorisation)
  static constexpr int kPathIterationWork = 43;       // per path-QP iteration
  static constexpr int kSpeedSolveSetupWork = 561;    // per speed QP, with its ST graph build
  static constexpr int kSpeedIterationWork = 39;      // per speed-QP iteration

  // QP storage (qp/qp_arena.hpp, docs/memory.md "QP arena"): false, each of
  // the coarse, path and speed QPs keeps its own problem and workspace and
  // every repeat of a stage's QP hotstarts; true, the three share one (the
  // path QP's size: about 80 KB less in double), and a stage that lost it to
  // another rebuilds its problem and restarts warm from its last working set.
  // That costs time: +25 % instructions per cycle on the default suite, the
  // measured maximum on the stress suite 13.9 -> 16.1 M (docs/memory.md).
  static constexpr bool kShareQpStorage = false;

  // Memory: sizeof(BasicPlanner<Cfg>) may not exceed this (checked at compile
  // time in planner.cpp on every target; docs/performance.md, "Memory").
  static constexpr unsigned long kPlannerBytesBudget = 294912;  // 288 KiB (287 920 B on x86-64, double)
};

template <class Sizes>
struct Configuration : Sizes {
  using Sizes::kMaxReferencePoints, Sizes::kMaxStaticObstacles, Sizes::kMaxDynamicObstacles;
  using Sizes::kPathBlocks, Sizes::kSpeedBlocks, Sizes::kKeptDecisions;
  using Sizes::kPathLength, Sizes::kMaxPathLength, Sizes::kSpeedHorizon, Sizes::kTrajectoryStep;

  // t = 0, step, ..., horizon
  static constexpr int kTrajectorySamples =
      static_cast<int>(kSpeedHorizon / kTrajectoryStep + Scalar(0.5)) + 1;
  // Objects in a scene (and decisions a plan reports: one per object).
  static constexpr int kMaxObstacles = kMaxStaticObstacles + kMaxDynamicObstacles;
  // Objects in the decision stage: the scene's, at most Sizes' decision capacities.
  static constexpr int kDecisionStatics = Sizes::kDecisionStaticObstacles < kMaxStaticObstacles
                                              ? Sizes::kDecisionStaticObstacles
                                              : kMaxStaticObstacles;
  static constexpr int kDecisionDynamics = Sizes::kDecisionDynamicObstacles < kMaxDynamicObstacles
                                               ? Sizes::kDecisionDynamicObstacles
                                               : kMaxDynamicObstacles;
  static constexpr int kMaxDecisionObstacles = kDecisionStatics + kDecisionDynamics;
  // Each SL box contributes at most two cuts in s, the road's edges at most
  // kMaxRoadCuts, hence at most 2N + 1 + kMaxRoadCuts slices.
  static constexpr int kMaxSlices = 2 * kMaxDecisionObstacles + 1 + Sizes::kMaxRoadCuts;
  static constexpr int kMaxZonesPerSlice = kMaxDecisionObstacles + 1;  // gaps between N intervals
  // All zones, tight: a slice holds at most (boxes overlapping it) + 1 zones,
  // and a box overlaps (cuts strictly inside it) + 1 slices. Of two boxes'
  // four ends at most two lie strictly inside the other box (nested or
  // overlapping), so box ends fall inside boxes at most N(N - 1) times, road
  // cuts at most N kMaxRoadCuts times:
  //   zones <= N(N - 1) + N kMaxRoadCuts + N + kMaxSlices
  // (N = 15, 8 road cuts: 384 instead of kMaxSlices x kMaxZonesPerSlice = 624;
  // tests/decision/test_convex_space.cpp builds a scene with exactly 384).
  static constexpr int kMaxZones =
      kMaxDecisionObstacles * (kMaxDecisionObstacles + Sizes::kMaxRoadCuts) + kMaxSlices;
  static constexpr int kKnotStates = 3;  // (value, 1st, 2nd derivative) per knot
  static constexpr int kPathVariables = (kPathBlocks + 1) * kKnotStates;
  static constexpr int kSpeedVariables = (kSpeedBlocks + 1) * kKnotStates;
  // Reference line: the polyline plus the points mirrored at each end.
  static constexpr int kMaxReferenceKnots = kMaxReferencePoints + 2 * config::kReferenceEndMirror;
  // kappa_ref(s) sampled every metre over the SL horizon.
  static constexpr int kCurvatureSamples = static_cast<int>(kPathLength + Scalar(0.5)) + 1;
  // Path QP: 5 samples per block, each with 4 rows (front and rear corridor, l', l'').
  static constexpr int kPathKnots = kPathBlocks + 1;
  static constexpr int kPathSamplesPerBlock = 5;
  static constexpr int kPathRowsPerSample = 4;
  static constexpr int kPathQpRows = kPathRowsPerSample * kPathSamplesPerBlock * kPathBlocks;
  // Speed QP: 5 samples per block, each with 3 rows (s, s', s''). The ST
  // graph and the speed bounds use the same samples, t_k = k horizon / kSpeedSamples.
  static constexpr int kSpeedKnots = kSpeedBlocks + 1;
  static constexpr int kSpeedSamplesPerBlock = 5;
  static constexpr int kSpeedSamples = kSpeedSamplesPerBlock * kSpeedBlocks;
  static constexpr int kStSamples = kSpeedSamples + 1;  // k = 0..kSpeedSamples
  static constexpr int kSpeedQpRows = 3 * kSpeedSamples;
  // Coarse decision QP: (l_i, t_i) at every coarse sample, one monotone-time row each.
  static constexpr int kCoarseQpVariables = 2 * Sizes::kCoarseSamples;
  static constexpr int kCoarseQpRows = Sizes::kCoarseSamples;

  static_assert(kPathLength >= Scalar(20) && kMaxPathLength >= kPathLength &&
                    kSpeedHorizon >= Scalar(1) && kTrajectoryStep > 0,
                "horizons too short to plan in");
  static_assert(kMaxReferencePoints >= 2 && Sizes::kMaxBoundaryPoints >= 1 &&
                    Sizes::kMaxPredictionSamples >= 1 && kMaxStaticObstacles >= 0 &&
                    kMaxDynamicObstacles >= 0 && Sizes::kMaxRoadCuts >= 0,
                "bad scene capacities");
  static_assert(kMaxZonesPerSlice <= 16, "zone successors are a 16-bit mask");
  static_assert(kMaxZones < 32767 && kMaxDecisionObstacles < 32767, "zone and box indices are int16");
  static_assert(kKeptDecisions >= 1 && Sizes::kMaxTreeNodes >= kMaxSlices &&
                    Sizes::kCoarseSamples >= 3,
                "bad decision sizes");
  static_assert(kPathBlocks >= 2 && kSpeedBlocks >= 2, "at least two QP blocks");
  static_assert(Sizes::kMaxPlannerIterations >= 1 && Sizes::kMaxPathSolvesPerCycle >= 1 &&
                    Sizes::kPathQpMaxIterations >= 1 && Sizes::kMaxDecisionRunsPerCycle >= 1 &&
                    Sizes::kCoarseQpMaxIterations >= 1 && Sizes::kSpeedQpMaxIterations >= 1 &&
                    Sizes::kMaxTreeNodesPerCycle >= 1 && Sizes::kMaxCoarseQpsPerCycle >= 1 &&
                    Sizes::kMaxCoarseIterationsPerCycle >= 1 && Sizes::kMaxPathIterationsPerCycle >= 1 &&
                    Sizes::kMaxSpeedSolvesPerCycle >= 1 && Sizes::kMaxSpeedIterationsPerCycle >= 1,
                "budgets must allow one solve");
  static_assert(Sizes::kCoarseQpSetupWork > 0 && Sizes::kCoarseIterationWork > 0 &&
                    Sizes::kPathSolveSetupWork > 0 && Sizes::kPathIterationWork > 0 &&
                    Sizes::kSpeedSolveSetupWork > 0 && Sizes::kSpeedIterationWork > 0 &&
                    Sizes::kQpWorkPerCycle >= Sizes::kPathSolveSetupWork + Sizes::kPathIterationWork &&
                    Sizes::kQpWorkPerCycle < 1000000000,
                "QP work costs must be positive and the cycle's work budget must allow one solve");
};

// The default build: the paper's envelope (10 static + 5 dynamic obstacles,
// 100 m, 7 s).
using DefaultConfig = Configuration<DefaultSizes>;
static_assert(DefaultConfig::kTrajectorySamples == 71, "plan/1 documents 71 samples over 7 s");
static_assert(DefaultConfig::kPathVariables == 63 && DefaultConfig::kSpeedVariables == 45 &&
                  DefaultConfig::kPathQpRows == 400 && DefaultConfig::kSpeedQpRows == 210,
              "QP shapes documented in docs/ assume these sizes");

}  // namespace itp
