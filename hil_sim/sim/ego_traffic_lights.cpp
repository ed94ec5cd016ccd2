#include "sim/ego_traffic_lights.hpp"

#include <cmath>
#include <vector>

#include "sim/box_geometry.hpp"

namespace hil::sim {
namespace {

constexpr double kLookAhead = 160.0;           // [m] stop lines farther ahead are not yet looked at
constexpr double kSameDirection = 0.7853981633974483;  // [rad] |lane heading - route heading| below: the route's lane
constexpr double kWallOverhang = 0.5;          // [m] beyond each road edge

}  // namespace

std::optional<StopWall> ego_stop_wall(const World& w, const LaneMap& lanes, std::span<const double> ref_arc,
                                      const EgoNow& ego, double now) {
  if (w.lanes.empty() || w.reference_line.size() < 2) return std::nullopt;
  const OrientedBox body = ego_box(Pose{ego.x, ego.y, ego.heading}, w.ego.length, w.ego.width, w.ego.wheelbase);
  const double front_s = project_to_polyline(w.reference_line, body.cx + 0.5 * body.length * std::cos(body.heading),
                                             body.cy + 0.5 * body.length * std::sin(body.heading))
                             .s;
  const double v = std::max(ego.v, 0.0);
  std::optional<StopWall> best;
  for (std::size_t i = 0; i < w.lanes.size(); ++i) {
    const Lane& lane = w.lanes[i];
    if (lane.traffic_lights.empty() || lane.centre.size() < 2) continue;
    const std::vector<double> arc = polyline_arc_lengths(lane.centre);
    const Pose line = polyline_pose(lane.centre, arc, lane.stop_s);
    const PolylineProjection on_route = project_to_polyline(w.reference_line, line.x, line.y);
    // The route's own lane: its stop line on the reference line, heading its way.
    if (std::fabs(on_route.l) > 0.5 * w.road.lane_width ||
        std::fabs(wrap_angle(line.heading - on_route.heading)) > kSameDirection) {
      continue;
    }
    const double room = on_route.s - front_s;  // [m] front bumper to the line
    if (room <= 0.0 || room > kLookAhead || (best && on_route.s >= best->line_s)) continue;
    const double needed = v * v / (2.0 * room);  // [m/s^2] to stop at the line
    // The lane's lights as the prediction reads them: red (or redYellow) with
    // `arriving`, any stop colour without.
    const bool red = lanes.stop_at(i, now, true);
    const bool stop = red ? needed <= kLightHardDecel : lanes.stop_at(i, now) && needed <= kLightComfortDecel;
    if (!stop) continue;
    // Across the drivable road just past the line.
    const double s = on_route.s + 0.5 * kStopWallDepth;
    const double left = w.road.left_boundary.at(s) + kWallOverhang;
    const double right = w.road.right_boundary.at(s) - kWallOverhang;
    const Pose c = polyline_pose(w.reference_line, ref_arc, s, 0.5 * (left + right));
    StopWall wall;
    wall.lane = lane.id;
    wall.line_s = on_route.s;
    wall.box.id = kStopWallIdBase + static_cast<int>(i);
    wall.box.x = c.x;
    wall.box.y = c.y;
    wall.box.heading = c.heading;
    wall.box.length = kStopWallDepth;
    wall.box.width = left - right;
    wall.box.kind = "stop_wall";
    best = wall;
  }
  return best;
}

}  // namespace hil::sim
