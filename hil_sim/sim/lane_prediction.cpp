#include "sim/lane_prediction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include "sim/box_geometry.hpp"
#include "sim/commonroad_route.hpp"

namespace hil::sim {
namespace {

constexpr double kLateralWeight = 0.2;   // [rad/m] in the match's ranking
constexpr double kJoinMerge = 0.1;       // [m] a successor's first point this close to the track's end is dropped

double distance_to_polygon(const std::vector<Point2>& poly, Point2 p) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    d = std::min(d, point_segment_distance(p, poly[i], poly[(i + 1) % poly.size()]));
  }
  return d;
}

double direction(Point2 a, Point2 b) { return std::atan2(b.y - a.y, b.x - a.x); }

}  // namespace

LaneMap::LaneMap(std::span<const Lane> lanes) : lanes_(lanes) {
  polygons_.reserve(lanes.size());
  for (const Lane& l : lanes) {
    std::vector<Point2> poly = l.left;
    poly.insert(poly.end(), l.right.rbegin(), l.right.rend());
    polygons_.push_back(std::move(poly));
  }
}

std::optional<LaneMatch> LaneMap::match(const Pose& c) const {
  std::optional<LaneMatch> best;
  auto rank = [&](const LaneMatch& m) {
    return std::make_tuple(!m.inside, std::fabs(m.heading_error) + kLateralWeight * std::fabs(m.l), lanes_[m.lane].id);
  };
  for (std::size_t i = 0; i < lanes_.size(); ++i) {
    const Lane& lane = lanes_[i];
    if (lane.centre.size() < 2 || polygons_[i].size() < 3) continue;
    const bool inside = polygon_contains(polygons_[i], {c.x, c.y});
    if (!inside && distance_to_polygon(polygons_[i], {c.x, c.y}) > kLaneMatchTolerance) continue;
    const PolylineProjection p = project_to_polyline(lane.centre, c.x, c.y);
    const double err = wrap_angle(c.heading - p.heading);
    if (std::fabs(err) > kLaneMatchMaxHeading) continue;
    const LaneMatch m{i, p.s, p.l, err, inside};
    if (!best || rank(m) < rank(*best)) best = m;
  }
  return best;
}

LaneTrack LaneMap::track(const LaneMatch& m, double length) const {
  std::map<long, std::size_t> by_id;
  for (std::size_t i = 0; i < lanes_.size(); ++i) by_id.emplace(lanes_[i].id, i);
  LaneTrack t;
  t.s0 = m.s;
  t.l0 = m.l;
  t.heading_error0 = m.heading_error;
  std::set<long> used;
  std::size_t cur = m.lane;
  t.line = lanes_[cur].centre;
  t.lanes.push_back(lanes_[cur].id);
  used.insert(lanes_[cur].id);
  t.arc = polyline_arc_lengths(t.line);
  if (!lanes_[cur].traffic_lights.empty()) t.stops.push_back({lanes_[cur].stop_s, cur});
  for (int k = 1; k < kMaxTrackLanes && t.arc.back() < m.s + length; ++k) {
    const Lane& here = lanes_[cur];
    const double end_dir = direction(here.centre[here.centre.size() - 2], here.centre.back());
    std::optional<std::size_t> next;
    double next_turn = 0.0;
    for (long id : here.successors) {
      const auto it = by_id.find(id);
      if (it == by_id.end() || used.count(id) > 0) continue;
      const Lane& s = lanes_[it->second];
      if (s.centre.size() < 2) continue;
      const double turn = std::fabs(wrap_angle(direction(s.centre.front(), s.centre.back()) - end_dir));
      if (!next || std::make_tuple(turn, id) < std::make_tuple(next_turn, lanes_[*next].id)) {
        next = it->second;
        next_turn = turn;
      }
    }
    if (!next) break;  // the map ends: polyline_pose goes on along the last segment
    cur = *next;
    used.insert(lanes_[cur].id);
    t.lanes.push_back(lanes_[cur].id);
    // The successor starts where the track ends (its first point is within
    // kJoinMerge of it, or the joint is a short straight piece).
    if (!lanes_[cur].traffic_lights.empty()) t.stops.push_back({t.arc.back() + lanes_[cur].stop_s, cur});
    for (const Point2& p : lanes_[cur].centre) {
      if (std::hypot(p.x - t.line.back().x, p.y - t.line.back().y) < kJoinMerge) continue;
      t.line.push_back(p);
    }
    t.arc = polyline_arc_lengths(t.line);
  }
  return t;
}

bool LaneMap::stop_at(std::size_t lane, double t, bool arriving) const {
  const std::vector<TrafficLightCycle>& lights = lanes_[lane].traffic_lights;
  if (lights.empty()) return false;
  return std::all_of(lights.begin(), lights.end(), [&](const TrafficLightCycle& c) {
    const std::string& color = light_color(c, t);
    return arriving ? color == "red" || color == "redYellow" : is_stop_color(color);
  });
}

TrackMotion track_motion(const LaneMap& map, const LaneTrack& track, double v, double front, double now,
                         double horizon) {
  constexpr double kLightScanStep = 0.05;  // [s] the lights are looked up this often while it stands
  TrackMotion m;
  m.speed = std::max(0.0, v);
  if (!(m.speed > 0.0)) return m;  // standing: it stays (as without lights)
  for (const TrackStop& stop : track.stops) {
    const double room = stop.s - kStopLineGap - (track.s0 + front);  // [m] front to where it stands
    if (room <= 0.0) continue;  // at or past the line: it drives on
    const double arrival = room / m.speed;  // [s] at constant speed
    if (!map.stop_at(stop.lane, now + arrival, true)) continue;  // not red then: it drives through
    const double decel = m.speed * m.speed / (2.0 * room);
    const double limit = map.stop_at(stop.lane, now, true) ? kRedLightFirmDecel : kRedLightMaxDecel;
    if (decel > limit) continue;  // cannot stop: it drives on
    m.stops = true;
    m.decel = decel;
    m.t_stop = m.speed / decel;
    m.stand = room;
    // It stands until no stop colour shows (looked up to the horizon's end).
    m.t_green = m.t_stop;
    while (m.t_green <= horizon && map.stop_at(stop.lane, now + m.t_green)) m.t_green += kLightScanStep;
    return m;
  }
  return m;
}

double track_distance(const TrackMotion& m, double t) {
  if (!m.stops) return m.speed * t;
  if (t <= m.t_stop) return m.speed * t - 0.5 * m.decel * t * t;
  if (t <= m.t_green) return m.stand;
  const double go = t - m.t_green;
  const double t_up = m.speed / kGreenStartAccel;  // [s] back at its speed
  if (go <= t_up) return m.stand + 0.5 * kGreenStartAccel * go * go;
  return m.stand + 0.5 * kGreenStartAccel * t_up * t_up + m.speed * (go - t_up);
}

Pose track_pose(const LaneTrack& track, double distance, double t) {
  const double l = track.l0 * std::max(0.0, 1.0 - t / kLateralOffsetDecay);
  const Pose p = polyline_pose(track.line, track.arc, track.s0 + distance, l);
  const double blend = std::max(0.0, 1.0 - t / kHeadingBlendTime);
  return Pose{p.x, p.y, wrap_angle(p.heading + blend * track.heading_error0)};
}

std::optional<std::vector<Pose>> predict_along_lanes(const LaneMap& map, const Pose& centre, double v,
                                                     std::span<const double> times, double now, double front) {
  if (map.empty() || times.empty()) return std::nullopt;
  const std::optional<LaneMatch> m = map.match(centre);
  if (!m) return std::nullopt;
  const double speed = std::max(0.0, v);
  const LaneTrack track = map.track(*m, speed * times.back() + front + 1.0);
  const TrackMotion motion = track_motion(map, track, speed, front, now, times.back());
  std::vector<Pose> out;
  out.reserve(times.size());
  for (double t : times) {
    out.push_back(t <= 0.0 ? centre : track_pose(track, track_distance(motion, t), t));
  }
  return out;
}

}  // namespace hil::sim
