#pragma once
// The scene the planner receives: one planning problem as plain
// fixed-capacity data (scene/1, docs/scene.md). Nothing here allocates;
// capacities come from the configuration (itp/config.hpp). Positions are in the world frame,
// angles counter-clockwise from +x.
#include <cstdint>

#include "itp/config.hpp"
#include "itp/core/static_vector.hpp"
#include "itp/geometry/point.hpp"
#include "itp/scene/vehicle.hpp"

namespace itp::scene {

using geometry::Point2;

// One [s, l] knot of a piecewise-linear road boundary.
struct BoundaryPoint {
  Scalar s = Scalar(0);  // [m] arc length along the reference line
  Scalar l = Scalar(0);  // [m] lateral offset, positive left
};

// A road edge as an offset l(s) from the reference line: the constant
// `offset` when `table` is empty, else linear between the table's knots
// (strictly ascending s) and constant beyond its first and last knots.
template <class Cfg>
struct BasicBoundary {
  Scalar offset = Scalar(0);                                   // [m]
  StaticVector<BoundaryPoint, Cfg::kMaxBoundaryPoints> table;  // [m, m]

  bool is_constant() const { return table.empty(); }
  Scalar at(Scalar s) const;  // [m] l of the edge at arc length s [m]
};

template <class Cfg>
struct BasicRoad {
  static constexpr Scalar kDefaultLaneWidth = Scalar(3.5);     // [m]
  static constexpr Scalar kDefaultEdgeOffset = Scalar(1.75);   // [m] |l| of either edge
  static constexpr Scalar kDefaultSpeedLimit = Scalar(13.9);   // [m/s]

  Scalar lane_width = kDefaultLaneWidth;                       // [m] width of one lane
  BasicBoundary<Cfg> left{kDefaultEdgeOffset, {}};             // [m] left edge of the drivable area (l > right)
  BasicBoundary<Cfg> right{-kDefaultEdgeOffset, {}};           // [m] right edge of the drivable area
  Scalar target_lane_offset = Scalar(0);    // [m] l of the target lane's centre
  Scalar speed_limit = kDefaultSpeedLimit;  // [m/s]

  // Back to a default-constructed road, in place (no temporary road).
  void reset() {
    lane_width = kDefaultLaneWidth;
    left.offset = kDefaultEdgeOffset;
    left.table.clear();
    right.offset = -kDefaultEdgeOffset;
    right.table.clear();
    target_lane_offset = Scalar(0);
    speed_limit = kDefaultSpeedLimit;
  }
};

// Ego state at t = 0; (x, y) is the centre of the rear axle.
struct EgoState {
  Scalar x = Scalar(0);        // [m]
  Scalar y = Scalar(0);        // [m]
  Scalar heading = Scalar(0);  // [rad]
  Scalar v = Scalar(0);        // [m/s] >= 0
  Scalar a = Scalar(0);        // [m/s^2]
  Scalar kappa = Scalar(0);    // [1/m] path curvature
};

struct Ego {
  EgoState state;
  VehicleGeometry geometry;
  VehicleLimits limits;
};

// A static obstacle: an oriented box, (x, y) its centre.
struct StaticObstacle {
  std::int32_t id = 0;
  Scalar x = Scalar(0);        // [m]
  Scalar y = Scalar(0);        // [m]
  Scalar heading = Scalar(0);  // [rad] direction of the length axis
  Scalar length = Scalar(0);   // [m]
  Scalar width = Scalar(0);    // [m]
};

// One time-stamped pose of a dynamic obstacle's box centre.
struct TimedPose {
  Scalar t = Scalar(0);        // [s] from the scene's start
  Scalar x = Scalar(0);        // [m]
  Scalar y = Scalar(0);        // [m]
  Scalar heading = Scalar(0);  // [rad]
  Scalar v = Scalar(0);        // [m/s] along heading
};

// A moving box with its trajectory (strictly ascending t). Absent before the
// first t; after the last it moves on at the last velocity and heading.
template <class Cfg>
struct BasicDynamicObstacle {
  std::int32_t id = 0;
  Scalar length = Scalar(0);  // [m]
  Scalar width = Scalar(0);   // [m]
  StaticVector<TimedPose, Cfg::kMaxPredictionSamples> trajectory;
};

// One planning problem with the capacities of configuration Cfg.
template <class Cfg>
struct BasicScene {
  StaticVector<Point2, Cfg::kMaxReferencePoints> reference_line;  // [m] lane centre, driving order
  BasicRoad<Cfg> road;
  Ego ego;
  StaticVector<StaticObstacle, Cfg::kMaxStaticObstacles> static_obstacles;
  StaticVector<BasicDynamicObstacle<Cfg>, Cfg::kMaxDynamicObstacles> dynamic_obstacles;

  // Back to a default-constructed scene, in place. `sc = BasicScene{}` would
  // build the ~20 KB temporary on the stack first (the firmware's deepest
  // stack path once did, docs/memory.md); this touches only sizes and the
  // scalar fields. Like that assignment it leaves the vectors' storage beyond
  // their (now zero) sizes as it was.
  void reset() {
    reference_line.clear();
    road.reset();
    ego.state = EgoState{};
    ego.geometry = VehicleGeometry{};
    ego.limits = VehicleLimits{};
    static_obstacles.clear();
    dynamic_obstacles.clear();
  }
};

// The default configuration's types.
using Boundary = BasicBoundary<DefaultConfig>;
using Road = BasicRoad<DefaultConfig>;
using DynamicObstacle = BasicDynamicObstacle<DefaultConfig>;
using Scene = BasicScene<DefaultConfig>;

}  // namespace itp::scene
