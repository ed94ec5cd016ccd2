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
inline constexpr int kKeptDecisions = 20;                // K best decisions evaluated
inline constexpr int kCoarseSamples = 20;                // coarse (l, t) samples per decision

// --- Path and speed QPs (paper 1.2, 1.3) ------------------------------------
inline constexpr int kPathBlocks = 20;                   // quintic SL blocks over kPathLength
inline constexpr int kSpeedBlocks = 14;                  // quintic ST blocks over kSpeedHorizon
inline constexpr int kKnotStates = 3;                    // (value, 1st, 2nd derivative) per knot
inline constexpr int kPathVariables = (kPathBlocks + 1) * kKnotStates;    // 63
inline constexpr int kSpeedVariables = (kSpeedBlocks + 1) * kKnotStates;  // 45

// --- Iteration (paper 2) ----------------------------------------------------
inline constexpr int kMaxPlannerIterations = 5;

// --- Serial link -------------------------------------------------------------
inline constexpr std::size_t kMaxPayloadBytes = 16384;   // one message body
inline constexpr std::size_t kBuildIdBytes = 48;         // fixed field in Pong

static_assert(kTrajectorySamples ==
              static_cast<int>(kSpeedHorizon / kTrajectoryStep + Scalar(0.5)) + 1,
              "trajectory samples must cover the speed horizon");
static_assert(kPathVariables == 63 && kSpeedVariables == 45,
              "QP shapes documented in docs/ assume these sizes");

}  // namespace config
}  // namespace itp
