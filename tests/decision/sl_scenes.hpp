#pragma once
// Hand-built SL scenes for the decision tests.
#include <vector>

#include "itp/decision/convex_space.hpp"

namespace decision_test {

using itp::Scalar;
using itp::decision::SlBox;

inline itp::decision::RoadSl road(Scalar right, Scalar left, Scalar target = 0) {
  itp::decision::RoadSl r;
  r.left = itp::decision::LateralProfile::constant(left);
  r.right = itp::decision::LateralProfile::constant(right);
  r.lane_width = 3.5;
  r.target_lane_offset = target;
  return r;
}

inline SlBox box(Scalar s0, Scalar s1, Scalar l0, Scalar l1, int id) {
  SlBox b;
  b.s_min = s0;
  b.s_max = s1;
  b.l_min = l0;
  b.l_max = l1;
  b.obstacle_id = id;
  return b;
}

inline itp::decision::ConvexSpaceParams params(Scalar ego_l = 0) {
  itp::decision::ConvexSpaceParams p;
  p.s_start = 0;
  p.s_end = 100;
  p.vehicle_width = 1.9;
  p.ego_l = ego_l;
  return p;
}

}  // namespace decision_test
