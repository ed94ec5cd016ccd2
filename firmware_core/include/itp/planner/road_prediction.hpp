#pragma once
// The obstacle motion the planner plans against, one pose per ST sample.
//
// Predictions arrive as time-stamped poses (scene/1). A straight-line one
// (constant heading and speed: what a constant-velocity extrapolation sends)
// of a road user on a curved road runs off along its tangent: across the
// ego's lane, or off the road, where the real car follows its lane. Such a
// prediction is re-read in the Frenet frame of the reference line: the
// obstacle keeps its speed along the road and its lateral offset, and a
// sideways motion (a lane change under way) ends at the next lane centre.
// Predictions that already turn (a prediction module that knows the road),
// movers crossing the road and obstacles off the road are used as given.
#include <array>

#include "itp/decision/road_sl.hpp"
#include "itp/geometry/reference_line.hpp"
#include "itp/scene/obstacle_motion.hpp"
#include "itp/scene/scene.hpp"

namespace itp::planner {

enum class PredictionUse : std::uint8_t {
  kAsGiven = 0,   // the samples are the prediction's own
  kFollowsRoad,   // a straight-line prediction re-read along the road
};

// `out[k]`: the obstacle at scene time now + k dt, k = 0 .. kStSamples-1.
// `road` gives the drivable edges (on the road or not where first seen) and
// the lane grid a lane change snaps to: centres at target_lane_offset + j
// lane_width.
template <class Cfg>
PredictionUse predict_along_road(const geometry::BasicReferenceLine<Cfg>& line,
                                 const decision::BasicRoadSl<Cfg>& road,
                                 const scene::BasicDynamicObstacle<Cfg>& obstacle, Scalar now,
                                 Scalar dt,
                                 std::array<scene::ObstacleSample, Cfg::kStSamples>& out);

}  // namespace itp::planner
