#pragma once
// Input validation: every way a scene can be unusable has its own reason
// (docs/scene.md). A rejected scene makes the planner answer invalid_input.
#include <cstdint>

#include "itp/core/status.hpp"
#include "itp/scene/scene.hpp"

namespace itp::scene {

enum class ValidationReason : std::uint8_t {
  kNone = 0,
  kNonFiniteValue,                // NaN or infinity in any number
  kCoordinateOutOfRange,          // |x| or |y| above kMaxCoordinate
  // Reference line
  kTooFewReferencePoints,         // fewer than 2
  kTooManyReferencePoints,        // above kMaxReferencePoints (reader overflow)
  kRepeatedReferencePoints,       // consecutive points closer than kMinReferencePointSpacing
  kReferenceLineSharpTurn,        // a kink or reversal beyond kMaxReferenceTurnPerPoint
  kReferenceLineTooShort,         // shorter than kMinReferenceLineLength
  // Road
  kLaneWidthOutOfRange,           // outside [kMinLaneWidth, kMaxLaneWidth]
  kBoundaryOutOfRange,            // |l| of a boundary above kMaxBoundaryOffset
  kTooManyBoundaryPoints,         // above kMaxBoundaryPoints (reader overflow)
  kBoundaryTableNotAscending,     // [s, l] table with non-increasing s
  kBoundariesCrossed,             // left <= right somewhere
  kTargetLaneOffsetOutOfRange,    // |target_lane_offset| above kMaxBoundaryOffset
  kSpeedLimitOutOfRange,          // <= 0 or above kMaxAbsoluteSpeed
  // Ego
  kEgoSpeedOutOfRange,            // v < 0 or above kMaxAbsoluteSpeed
  kEgoAccelerationOutOfRange,     // |a| above kMaxAbsoluteAcceleration
  kEgoCurvatureOutOfRange,        // |kappa| above kMaxAbsoluteCurvature
  kEgoGeometryOutOfRange,         // size <= 0 or above kMaxObjectSize, wheelbase >= length
  kEgoLimitsOutOfRange,           // a_min >= 0, a_max <= 0, lat_acc_max <= 0, kappa_max <= 0 or absurd
  kEgoFarFromReferenceLine,       // farther than kMaxEgoOffsetFromReference from the polyline
  // Obstacles
  kTooManyStaticObstacles,        // above kMaxStaticObstacles (reader overflow)
  kTooManyDynamicObstacles,       // above kMaxDynamicObstacles (reader overflow)
  kObstacleSizeOutOfRange,        // length/width <= 0 or above kMaxObjectSize
  kDuplicateObstacleId,           // two obstacles (static or dynamic) share an id
  kEmptyTrajectory,               // dynamic obstacle without samples
  kTooManyPredictionSamples,      // above kMaxPredictionSamples (reader overflow)
  kPredictionTimesNotIncreasing,  // t not strictly ascending
  kPredictionTimeOutOfRange,      // |t - now| above kMaxPredictionTime
  kObstacleSpeedOutOfRange,       // |v| above kMaxAbsoluteSpeed
  // Added with protocol version 2 (the numbers travel in Plan replies: append only)
  kSceneTimeOutOfRange,           // now < 0, above kMaxSceneTime, or not finite
  kHeadingOutOfRange,             // |heading| of the ego, an obstacle or a sample above kMaxAbsoluteHeading
};

// Stable snake_case name (used as plan/1 "reason").
const char* to_string(ValidationReason reason);

struct ValidationResult {
  ValidationReason reason = ValidationReason::kNone;
  std::int16_t index = -1;      // offending point / obstacle / boundary (0 left, 1 right), or -1
  std::int16_t sub_index = -1;  // offending trajectory sample, or -1

  bool ok() const { return reason == ValidationReason::kNone; }
  PlanStatus status() const { return ok() ? PlanStatus::kOk : PlanStatus::kInvalidInput; }
};

// Checks everything the planner relies on for a scene planned at time `now`
// [s], first problem found wins (order: scene time, reference line, road,
// ego, static then dynamic obstacles, ids; within each, non-finite values
// before ranges). Prediction times are judged relative to `now`, so nothing
// expires however long the scene clock runs. Bounded by the scene's
// capacities; no allocation, no spline fit (the reference line is checked
// as a polyline).
template <class Cfg>
ValidationResult validate(const BasicScene<Cfg>& scene, Scalar now);

// The checks that do not need the scene time: the same as above, except
// that prediction times are only bounded by kMaxSceneTime + kMaxPredictionTime
// and `now` is not looked at. Callers that know the scene time use the other.
template <class Cfg>
ValidationResult validate(const BasicScene<Cfg>& scene);

}  // namespace itp::scene
