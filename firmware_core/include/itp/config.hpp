#pragma once
// The one configuration header: every size, capacity and loop bound of the
// planner derives from the constexpr values here. Raising a capacity is a
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

// --- Planning horizon (paper, Table 1) ------------------------------------
inline constexpr Scalar kPathLength = Scalar(100);       // [m] SL horizon
inline constexpr Scalar kSpeedHorizon = Scalar(7);       // [s] ST horizon
inline constexpr Scalar kTrajectoryStep = Scalar(0.1);   // [s] output sample step
inline constexpr int kTrajectorySamples = 71;            // t = 0, 0.1, ..., 7.0 s

// --- Scene capacities ------------------------------------------------------
inline constexpr int kMaxReferencePoints = 128;          // reference-line polyline points
inline constexpr int kMaxBoundaryPoints = 32;            // [s, l] pairs per road boundary
inline constexpr int kMaxStaticObstacles = 10;
inline constexpr int kMaxDynamicObstacles = 5;
inline constexpr int kMaxPredictionSamples = 80;         // poses per dynamic obstacle

// --- Convex space and decision (paper 1.1) ---------------------------------
// Each obstacle contributes at most two cuts in s, hence at most 2N+1 slices.
inline constexpr int kMaxObstacles = kMaxStaticObstacles + kMaxDynamicObstacles;
inline constexpr int kMaxSlices = 2 * kMaxObstacles + 1;
inline constexpr int kMaxZonesPerSlice = kMaxObstacles + 1;  // gaps between N intervals
inline constexpr int kMaxZones = kMaxSlices * kMaxZonesPerSlice;
inline constexpr int kKeptDecisions = 20;                // K best decisions evaluated
// Decision-tree search: nodes (zone visits) expanded per cycle, at most. The
// branch-and-bound search stops there and keeps the best K found so far.
inline constexpr int kMaxTreeNodes = 4096;
inline constexpr int kCoarseSamples = 20;                // coarse (l, t) samples per decision

// --- Path and speed QPs (paper 1.2, 1.3) ------------------------------------
inline constexpr int kPathBlocks = 20;                   // quintic SL blocks over kPathLength
inline constexpr int kSpeedBlocks = 14;                  // quintic ST blocks over kSpeedHorizon
inline constexpr int kKnotStates = 3;                    // (value, 1st, 2nd derivative) per knot
inline constexpr int kPathVariables = (kPathBlocks + 1) * kKnotStates;    // 63
inline constexpr int kSpeedVariables = (kSpeedBlocks + 1) * kKnotStates;  // 45

// --- Iteration (paper 2) ----------------------------------------------------
inline constexpr int kMaxPlannerIterations = 5;
inline constexpr int kRememberedInfeasibleCorridors = 16;  // per cycle: path QPs not repeated on them
inline constexpr int kMaxPathSolvesPerCycle = 16;          // path QP budget per cycle (bounds the worst case)
inline constexpr int kPathQpMaxIterations = 60;            // path QP iteration cap (infeasible ones stop early)
// Decision-stage runs (convex space, tree, up to kKeptDecisions coarse QPs) per
// cycle, over all iterations and their rounds (a round leaves one more moving
// obstacle to the ST graph); without it up to kMaxPlannerIterations x
// (kMaxDynamicObstacles + 1) = 30. A cycle that needs more falls back (WCET
// bound). Closed loop, seeds 1-3 (72 000 cycles): 99.9 % of ok cycles need
// <= 15, and 15 costs < 1 % more fallbacks (12: 2-4 %, 10: 5-7 %).
inline constexpr int kMaxDecisionRunsPerCycle = 15;

// --- Reference line and Frenet frame (docs/frenet.md) -------------------------
// The smoothing spline is fitted through the polyline plus up to
// kReferenceEndMirror points mirrored at each end, covering at least
// kReferenceMirrorLength (so the natural end condition, kappa = 0, acts far
// from the real ends and does not flatten their curvature).
inline constexpr int kReferenceEndMirror = 16;
inline constexpr Scalar kReferenceMirrorLength = Scalar(15);   // [m] ~7 smoothing bandwidths
inline constexpr int kMaxReferenceKnots = kMaxReferencePoints + 2 * kReferenceEndMirror;
inline constexpr Scalar kReferenceSmoothing = Scalar(16);       // [m^3] spline penalty lambda
                                                                // (bandwidth lambda^(1/4) = 2 m)
inline constexpr Scalar kMinReferencePointSpacing = Scalar(0.05);  // [m] closer = repeated point
inline constexpr Scalar kMaxReferenceTurnPerPoint = Scalar(1.0471975511965976);  // [rad] 60 deg
inline constexpr Scalar kMinReferenceLineLength = Scalar(20);   // [m]
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
inline constexpr Scalar kMaxCoordinate = Scalar(1.0e5);         // [m] |x|, |y|
inline constexpr Scalar kMaxPredictionTime = Scalar(3600);      // [s] obstacle trajectory t
inline constexpr Scalar kMaxEgoOffsetFromReference = Scalar(10);  // [m] ego to polyline

// --- Serial link -------------------------------------------------------------
inline constexpr std::size_t kMaxPayloadBytes = 32768;   // one message body (a path QP or a scene)
inline constexpr std::size_t kBuildIdBytes = 48;         // fixed field in Pong

static_assert(kTrajectorySamples ==
              static_cast<int>(kSpeedHorizon / kTrajectoryStep + Scalar(0.5)) + 1,
              "trajectory samples must cover the speed horizon");
static_assert(kPathVariables == 63 && kSpeedVariables == 45,
              "QP shapes documented in docs/ assume these sizes");

}  // namespace config
}  // namespace itp
