#pragma once
// A CommonRoad shape (rectangles, circles, polygons, or a group of them, in
// the obstacle's own frame) as the one oriented box scene/1 carries per
// obstacle (docs/commonroad.md, "Obstacles").
#include "formats/commonroad.hpp"
#include "sim/world.hpp"

namespace hil::sim {

// The box in the obstacle's frame: placed in the world by the state, centre
// = position + R(orientation) * centre, heading = orientation + heading_offset.
struct LocalBox {
  double length = 0.0;          // [m] along heading_offset
  double width = 0.0;           // [m]
  double heading_offset = 0.0;  // [rad] relative to the obstacle's orientation
  Point2 centre;                // [m] in the obstacle's frame
};

// The smallest-area box holding the whole shape. `aligned` (dynamic
// obstacles) keeps it aligned with the obstacle's orientation, so that
// scene/1's "moves on along its heading" stays true; otherwise the
// orientation of each rectangle and the direction of each polygon edge are
// tried (exact for one rectangle, and the minimum-area box of one convex
// polygon, which has a side on one of its edges).
LocalBox bounding_box(const formats::commonroad::Shape& shape, bool aligned);

// The box of a state's pose in the world.
Pose place(const LocalBox& box, double x, double y, double orientation);

}  // namespace hil::sim
