#pragma once
// The ego's own traffic lights (CommonRoad <trafficLight>, World::lanes).
// The planner knows no traffic lights; what it stops for is a blocked road.
// So where the ego's route crosses a lane's stop line while that lane's
// lights tell traffic to stop, the planner's scene gets a stop wall: a thin
// static box across the drivable road just past the line. The wall is the
// planner's only: the world, its obstacles and the collision metrics never
// contain it.
//
// When the ego stops for a light (as a driver does):
//   red, redYellow: if it can still stop before the line at the vehicle's
//     braking limit (past that point it is committed and drives on);
//   yellow: if it can stop before the line at comfortable braking.
#include <optional>
#include <span>

#include "sim/lane_prediction.hpp"
#include "sim/scene_convert.hpp"
#include "sim/world.hpp"

namespace hil::sim {

inline constexpr double kLightHardDecel = 6.0;     // [m/s^2] the braking limit a red light may ask
inline constexpr double kLightComfortDecel = 3.0;  // [m/s^2] what a yellow light may ask
inline constexpr double kStopWallDepth = 0.5;      // [m] along the road
inline constexpr int kStopWallIdBase = 1'000'000'000;  // + the lane's index: above every map id

struct StopWall {
  StaticObstacle box;   // in the world frame, id kStopWallIdBase + lane index
  long lane = 0;        // the lane whose light it is
  double line_s = 0.0;  // [m] the stop line's arc length along the world's reference line
};

// The nearest stop wall ahead of the ego at scene time `now`, if any.
// `lanes`: LaneMap(world.lanes); `ref_arc`: polyline_arc_lengths(world.reference_line).
std::optional<StopWall> ego_stop_wall(const World& world, const LaneMap& lanes, std::span<const double> ref_arc,
                                      const EgoNow& ego, double now);

}  // namespace hil::sim
