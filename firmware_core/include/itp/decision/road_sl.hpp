#pragma once
// The drivable area in the SL frame: left and right edges as piecewise-linear
// functions of s, and the target lane. Built from the scene by the planner.
#include <array>
#include <span>

#include "itp/config.hpp"
#include "itp/core/static_vector.hpp"

namespace itp::decision {

// l(s), piecewise linear through (s, l) points sorted by s; constant beyond
// the ends; a single point is a constant.
template <class Cfg>
class BasicLateralProfile {
 public:
  struct Point {
    Scalar s;  // [m]
    Scalar l;  // [m]
  };

  static BasicLateralProfile constant(Scalar l);
  // Returns false when full or when s does not increase.
  [[nodiscard]] bool add(Scalar s, Scalar l);

  Scalar at(Scalar s) const;
  // Extremes of l over [s0, s1] (at the ends or at interior points).
  Scalar min_over(Scalar s0, Scalar s1) const;
  Scalar max_over(Scalar s0, Scalar s1) const;
  bool empty() const { return points_.empty(); }
  std::span<const Point> points() const { return points_.span(); }

 private:
  StaticVector<Point, Cfg::kMaxBoundaryPoints> points_;
};

template <class Cfg>
struct BasicRoadSl {
  BasicLateralProfile<Cfg> left;            // [m] drivable edge, l grows to the left
  BasicLateralProfile<Cfg> right;           // [m]
  Scalar lane_width = Scalar(3.5);          // [m]
  Scalar target_lane_offset = Scalar(0);    // [m] l of the target lane's centre
  // Extra slice edges of the convex space where the edges change
  // (select_road_cuts), ascending; empty for edges that are constant.
  StaticVector<Scalar, Cfg::kMaxRoadCuts> cuts;
};

// Chooses road.cuts within (s0, s1): a slice of the convex space takes the
// narrowest road over its length, so where an edge moves (a narrowing, a
// lane that ends) one long slice would lose the width of the whole change,
// also where the ego is. Greedy, at most Cfg::kMaxRoadCuts times: the slice
// losing the largest area (length x lost width) is split where the two
// halves lose the least (at a knot of either edge, else in the middle of a
// straight stretch). Slices losing at most `tolerance` of width, or shorter
// than `min_length`, are not split.
template <class Cfg>
void select_road_cuts(BasicRoadSl<Cfg>& road, Scalar s0, Scalar s1, Scalar tolerance, Scalar min_length);

using LateralProfile = BasicLateralProfile<DefaultConfig>;
using RoadSl = BasicRoadSl<DefaultConfig>;

}  // namespace itp::decision
