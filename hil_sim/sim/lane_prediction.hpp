#pragma once
// Lane-following prediction (`hil_sim run --prediction lane`): a road user on
// a lane of the world's lane map (World::lanes, the CommonRoad lanelets) is
// predicted to drive on along that lane's centre line and its successors at
// its current speed, instead of straight on along its heading. On a curve a
// constant-velocity prediction leaves the lane along the tangent (at
// USA_Peach-4_8 it put an oncoming car into the ego's lane); a driver follows
// the lane. Where no lane matches (off the map, a heading far from every
// lane's direction, a pedestrian, a world without a lane map) the caller uses
// constant velocity. docs/simulation.md, "Predictions".
#include <optional>
#include <span>
#include <vector>

#include "sim/world.hpp"

namespace hil::sim {

// An obstacle's centre matches a lane when it lies inside the lane's polygon
// (left bound, then the right bound reversed), or within kLaneMatchTolerance of
// it, and its heading is within kLaneMatchMaxHeading of the centre line's
// direction at its foot point.
inline constexpr double kLaneMatchTolerance = 0.5;        // [m]
inline constexpr double kLaneMatchMaxHeading = 0.785398;  // [rad] pi/4
// The lateral offset from the centre line at the start decays linearly to 0
// over this time (drivers keep to the lane's centre), and the heading's
// difference from the lane's direction over kHeadingBlendTime.
inline constexpr double kLateralOffsetDecay = 3.0;  // [s]
inline constexpr double kHeadingBlendTime = 1.0;    // [s]
// Successor lanes chained into one track, at most (loops are cut anyway).
inline constexpr int kMaxTrackLanes = 64;
// Traffic lights (Lane::traffic_lights): a road user whose front would reach
// a stop line while its lane's lights show red (or redYellow) at the time it
// gets there at its current speed (the cycles are known) brakes evenly to
// stand kStopLineGap before the line, if that needs at most kRedLightMaxDecel
// (the deceleration yellow intervals are designed for, ITE: 10 ft/s^2), or
// kRedLightFirmDecel when the light shows red already; one that would need
// more drives on. One that gets there during yellow drives
// on (it may enter on yellow; predicting a stop it does not make would be
// the unsafe error for whoever crosses its path). It stands until the lights
// show no stop colour (red, yellow, redYellow), then accelerates at
// kGreenStartAccel back to its speed. Only the first stop line where it stops
// is modelled.
inline constexpr double kRedLightMaxDecel = 3.05;  // [m/s^2]
// ... and when the light shows red already (its driver has had the whole
// yellow to slow down): firm braking, not an emergency stop.
inline constexpr double kRedLightFirmDecel = 5.0;  // [m/s^2]
inline constexpr double kStopLineGap = 0.5;        // [m] front bumper to the line
inline constexpr double kGreenStartAccel = 2.0;    // [m/s^2]

struct LaneMatch {
  std::size_t lane = 0;        // index into the map's lanes
  double s = 0.0;              // [m] foot point along the lane's centre line
  double l = 0.0;              // [m] lateral offset, left positive
  double heading_error = 0.0;  // [rad] obstacle heading - lane direction, wrapped
  bool inside = true;          // inside the polygon (else within the tolerance)
};

// The centre line an obstacle follows: its lane from the start, then one
// successor after the other (at a branch the straightest: the smallest angle
// between the successor's overall direction, first to last centre point, and
// the current lane's end direction; ties to the lower id).
struct TrackStop {
  double s = 0.0;     // [m] the stop line on `line`
  std::size_t lane = 0;  // index into the map's lanes (its traffic lights)
};

struct LaneTrack {
  std::vector<Point2> line;
  std::vector<double> arc;  // [m] arc lengths of `line`
  std::vector<long> lanes;  // the lane ids chained
  std::vector<TrackStop> stops;  // the chained lanes' stop lines, ascending s
  double s0 = 0.0;          // [m] the obstacle's foot point on `line`
  double l0 = 0.0;          // [m] its lateral offset there
  double heading_error0 = 0.0;
};

class LaneMap {
 public:
  explicit LaneMap(std::span<const Lane> lanes);
  bool empty() const { return lanes_.empty(); }

  // The best matching lane: inside before within the tolerance, then the
  // smallest |heading error| + 0.2 rad/m |l|, then the lower id.
  std::optional<LaneMatch> match(const Pose& centre) const;

  // The track from the match on, at least `length` metres beyond the foot
  // point where the map goes on (a track ending earlier is extended straight
  // along its last segment by polyline_pose).
  LaneTrack track(const LaneMatch& m, double length) const;

  // Whether every traffic light of lane `lane` shows a stop colour at scene
  // time t (false for a lane without lights); with `arriving`, red or
  // redYellow only (yellow lets an arriving car enter).
  bool stop_at(std::size_t lane, double t, bool arriving = false) const;

 private:
  std::span<const Lane> lanes_;
  std::vector<std::vector<Point2>> polygons_;
};

// The obstacle's box centre and heading `t` seconds on, having driven `distance`
// metres along the track.
Pose track_pose(const LaneTrack& track, double distance, double t);

// How a road user moves along its track from scene time `now`: at its speed,
// or braking evenly to a stop at the first red light's line it can stop for
// (above), standing there until the lights show no stop colour (looked up to
// `horizon` seconds on), then back up to its speed. `front`: its box centre
// to its front bumper.
struct TrackMotion {
  double speed = 0.0;    // [m/s]
  bool stops = false;    // at a red light within reach
  double decel = 0.0;    // [m/s^2] > 0 when it stops
  double t_stop = 0.0;   // [s] standing from then
  double stand = 0.0;    // [m] where it stands, from its foot point
  double t_green = 0.0;  // [s] going again from then
};
TrackMotion track_motion(const LaneMap& map, const LaneTrack& track, double v, double front, double now,
                         double horizon);
// The distance driven along the track by `t` seconds on.
double track_distance(const TrackMotion& motion, double t);

// The whole prediction: poses at times `times` (from now, ascending, >= 0)
// at constant speed v along the matched lane, stopping at red lights (scene
// time `now`; `front`: the box centre to its front bumper); nullopt when no
// lane matches.
std::optional<std::vector<Pose>> predict_along_lanes(const LaneMap& map, const Pose& centre, double v,
                                                     std::span<const double> times, double now = 0.0,
                                                     double front = 0.0);

}  // namespace hil::sim
