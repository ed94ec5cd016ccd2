#pragma once
// Oriented boxes (vehicle and obstacle footprints) and the two questions the
// planner asks of them: do two boxes overlap (separating axis theorem), and
// how far apart are they (exact, 0 when overlapping). Constant work: 4 axes,
// 32 point-segment distances.
#include <array>

#include "itp/config.hpp"

namespace itp::collision {

struct OrientedBox {
  Scalar cx = 0;       // [m] centre
  Scalar cy = 0;       // [m]
  Scalar heading = 0;  // [rad] direction of the length axis
  Scalar length = 0;   // [m]
  Scalar width = 0;    // [m]
};

struct Corner {
  Scalar x = 0;
  Scalar y = 0;
};

// Counter-clockwise from the front-left corner.
std::array<Corner, 4> corners(const OrientedBox& box);

// The ego's box from its rear-axle pose: the centre lies (length/2 - rear_overhang) ahead.
OrientedBox box_from_rear_axle(Scalar x, Scalar y, Scalar heading, Scalar length, Scalar width,
                               Scalar rear_overhang);

bool overlap(const OrientedBox& a, const OrientedBox& b);

// Euclidean distance between the two boxes' areas; 0 when they overlap.
Scalar distance(const OrientedBox& a, const OrientedBox& b);

}  // namespace itp::collision
