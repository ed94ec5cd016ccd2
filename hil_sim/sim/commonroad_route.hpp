#pragma once
// The ego's road from a CommonRoad lanelet network (docs/commonroad.md, "Road"):
// the lanelet that holds the ego, the route through its successors (and a few
// predecessors behind it), the route's centre line as the reference line, and
// the drivable area across it (the route's lanelets and their same-direction
// neighbours, optionally the opposite-direction ones) as [s, l] edges that
// never lie outside the lanelets' outer bounds.
#include <optional>
#include <string>
#include <vector>

#include "formats/commonroad.hpp"
#include "sim/world.hpp"

namespace hil::sim {

struct RouteOptions {
  bool opposite_lanes = false;    // the road includes opposite-direction neighbours
  double length_ahead = 300.0;    // [m] of route wanted ahead of the ego
  double length_behind = 30.0;    // [m] wanted behind it
  std::vector<long> goal_lanelets;  // successors leading here are preferred
};

struct LaneRoute {
  std::vector<long> lanelets;          // driving order, predecessors behind the ego first
  std::size_t ego_index = 0;           // the ego's lanelet in `lanelets`
  std::vector<Point2> reference_line;  // [m] the route's centre line
  Boundary left;                       // [s, l] along reference_line
  Boundary right;
  double lane_width = 3.5;             // [m] the ego lanelet's width at the ego
  std::vector<long> road_lanelets;     // route lanelets and the neighbours the road includes
  std::vector<std::string> notes;      // choices worth telling (a branch taken, a loop cut)
};

struct RouteResult {
  std::optional<LaneRoute> route;
  std::string error;  // names the element: "lanelet 12: successor 13 does not exist"
};

// `ego` is the position CommonRoad gives (the vehicle's centre) and its orientation.
RouteResult build_route(const formats::commonroad::Scenario& scenario, const Pose& ego, const RouteOptions& options);

// The centre polyline of a lanelet: midpoints of paired bound vertices when
// both bounds have as many (CommonRoad's own convention), else of both bounds
// resampled at the same fractions of their lengths.
std::vector<Point2> lanelet_centre(const formats::commonroad::Lanelet& lanelet);

// The lanelet's area as a polygon: the left bound, then the right bound reversed.
std::vector<Point2> lanelet_polygon(const formats::commonroad::Lanelet& lanelet);

// Point in polygon (even-odd rule; points on an edge count as inside).
bool polygon_contains(const std::vector<Point2>& polygon, Point2 p);

}  // namespace hil::sim
