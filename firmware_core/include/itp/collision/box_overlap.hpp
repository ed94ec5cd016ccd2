#pragma once
// The two questions the planner asks of footprints (geometry::OrientedBox):
// do two boxes overlap (separating axis theorem), and how far apart are they
// (exact, 0 when overlapping). Constant work: 4 axes, 32 point-segment
// distances.
#include "itp/geometry/oriented_box.hpp"

namespace itp::collision {

using geometry::OrientedBox;

bool overlap(const OrientedBox& a, const OrientedBox& b);

// Euclidean distance between the two boxes' areas; 0 when they overlap.
Scalar distance(const OrientedBox& a, const OrientedBox& b);

}  // namespace itp::collision
