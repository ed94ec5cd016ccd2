#include "itp/scene/validation.hpp"

namespace itp::scene {

const char* to_string(ValidationReason reason) {
  switch (reason) {
    case ValidationReason::kNone: return "none";
    case ValidationReason::kNonFiniteValue: return "non_finite_value";
    case ValidationReason::kCoordinateOutOfRange: return "coordinate_out_of_range";
    case ValidationReason::kTooFewReferencePoints: return "too_few_reference_points";
    case ValidationReason::kTooManyReferencePoints: return "too_many_reference_points";
    case ValidationReason::kRepeatedReferencePoints: return "repeated_reference_points";
    case ValidationReason::kReferenceLineSharpTurn: return "reference_line_sharp_turn";
    case ValidationReason::kReferenceLineTooShort: return "reference_line_too_short";
    case ValidationReason::kLaneWidthOutOfRange: return "lane_width_out_of_range";
    case ValidationReason::kBoundaryOutOfRange: return "boundary_out_of_range";
    case ValidationReason::kTooManyBoundaryPoints: return "too_many_boundary_points";
    case ValidationReason::kBoundaryTableNotAscending: return "boundary_table_not_ascending";
    case ValidationReason::kBoundariesCrossed: return "boundaries_crossed";
    case ValidationReason::kTargetLaneOffsetOutOfRange: return "target_lane_offset_out_of_range";
    case ValidationReason::kSpeedLimitOutOfRange: return "speed_limit_out_of_range";
    case ValidationReason::kEgoSpeedOutOfRange: return "ego_speed_out_of_range";
    case ValidationReason::kEgoAccelerationOutOfRange: return "ego_acceleration_out_of_range";
    case ValidationReason::kEgoCurvatureOutOfRange: return "ego_curvature_out_of_range";
    case ValidationReason::kEgoGeometryOutOfRange: return "ego_geometry_out_of_range";
    case ValidationReason::kEgoLimitsOutOfRange: return "ego_limits_out_of_range";
    case ValidationReason::kEgoFarFromReferenceLine: return "ego_far_from_reference_line";
    case ValidationReason::kTooManyStaticObstacles: return "too_many_static_obstacles";
    case ValidationReason::kTooManyDynamicObstacles: return "too_many_dynamic_obstacles";
    case ValidationReason::kObstacleSizeOutOfRange: return "obstacle_size_out_of_range";
    case ValidationReason::kDuplicateObstacleId: return "duplicate_obstacle_id";
    case ValidationReason::kEmptyTrajectory: return "empty_trajectory";
    case ValidationReason::kTooManyPredictionSamples: return "too_many_prediction_samples";
    case ValidationReason::kPredictionTimesNotIncreasing: return "prediction_times_not_increasing";
    case ValidationReason::kPredictionTimeOutOfRange: return "prediction_time_out_of_range";
    case ValidationReason::kObstacleSpeedOutOfRange: return "obstacle_speed_out_of_range";
    case ValidationReason::kSceneTimeOutOfRange: return "scene_time_out_of_range";
    case ValidationReason::kHeadingOutOfRange: return "heading_out_of_range";
  }
  return "unknown";
}

}  // namespace itp::scene
