#include "sim/scene_convert.hpp"

#include <algorithm>
#include <cmath>

#include "sim/box_geometry.hpp"

namespace hil::sim {
namespace {

constexpr double kBehind = 40.0;              // [m] of reference line kept behind the ego (rear traffic)
constexpr double kAhead = itp::DefaultConfig::kMaxPathLength + 20.0;  // [m] kept ahead
constexpr double kPredictionStep = 0.1;       // [s]
constexpr double kPredictionSpan = itp::DefaultConfig::kSpeedHorizon + 0.5;  // [s]
constexpr double kRelevantRange = 160.0;      // [m] obstacles farther from the ego are left out

bool copy_boundary(const Boundary& from, double s0, itp::scene::Boundary& to, std::string& error) {
  to.offset = from.constant;
  to.table.clear();
  if (from.is_constant()) {
    return true;
  }
  // Knots inside the window plus one on each side, shifted to the window's s.
  for (std::size_t i = 0; i < from.knots.size(); ++i) {
    const double s = from.knots[i].s - s0;
    const bool next_inside = i + 1 < from.knots.size() && from.knots[i + 1].s - s0 >= 0;
    const bool prev_inside = i > 0 && from.knots[i - 1].s - s0 <= kBehind + kAhead;
    if ((s >= 0 && s <= kBehind + kAhead) || (s < 0 && next_inside) || (s > kBehind + kAhead && prev_inside)) {
      if (!to.table.push_back({s, from.knots[i].l})) {
        error = "road boundary has more knots in the window than the planner holds";
        return false;
      }
    }
  }
  if (to.table.empty()) {
    to.offset = from.at(s0);
  }
  return true;
}

}  // namespace

EgoNow ego_at_start(const World& w) {
  return EgoNow{w.ego.x, w.ego.y, w.ego.heading, w.ego.v, w.ego.a, w.ego.kappa};
}

ConvertResult make_planner_scene(const World& w, const EgoNow& ego, double now, Prediction mode,
                                 itp::scene::Scene& out) {
  ConvertResult res;
  out = itp::scene::Scene{};
  if (w.reference_line.size() < 2) {
    res.error = "reference line has fewer than 2 points";
    return res;
  }
  const std::vector<double> arc = polyline_arc_lengths(w.reference_line);
  const double s_ego = project_to_polyline(w.reference_line, ego.x, ego.y).s;
  std::size_t first = 0;
  while (first + 1 < w.reference_line.size() && arc[first + 1] <= s_ego - kBehind) {
    ++first;
  }
  for (std::size_t i = first; i < w.reference_line.size() && arc[i] <= s_ego + kAhead; ++i) {
    if (!out.reference_line.push_back({w.reference_line[i].x, w.reference_line[i].y})) {
      break;  // the window is as long as the capacity allows
    }
  }
  res.window_s0 = arc[first];
  out.road.lane_width = w.road.lane_width;
  out.road.target_lane_offset = w.road.target_lane_offset;
  out.road.speed_limit = w.road.speed_limit;
  if (!copy_boundary(w.road.left_boundary, res.window_s0, out.road.left, res.error) ||
      !copy_boundary(w.road.right_boundary, res.window_s0, out.road.right, res.error)) {
    return res;
  }
  out.ego.state = {ego.x, ego.y, ego.heading, ego.v, ego.a, ego.kappa};
  out.ego.geometry = {w.ego.length, w.ego.width, w.ego.wheelbase};

  for (const StaticObstacle& o : w.static_obstacles) {
    if (std::hypot(o.x - ego.x, o.y - ego.y) > kRelevantRange) {
      continue;
    }
    if (!out.static_obstacles.push_back({o.id, o.x, o.y, o.heading, o.length, o.width})) {
      res.error = "more static obstacles in range than the planner holds";
      return res;
    }
  }
  for (const DynamicObstacle& o : w.dynamic_obstacles) {
    const std::optional<Pose> current = pose_at(o, now);
    const double v_now = [&] {
      for (std::size_t i = 0; i + 1 < o.trajectory.size(); ++i) {
        if (o.trajectory[i + 1].t >= now) return o.trajectory[i].v;
      }
      return o.trajectory.back().v;
    }();
    if (mode == Prediction::kConstantVelocity && !current) {
      continue;  // not perceived yet
    }
    if (current && std::hypot(current->x - ego.x, current->y - ego.y) > kRelevantRange) {
      continue;
    }
    itp::scene::DynamicObstacle d;
    d.id = o.id;
    d.length = o.length;
    d.width = o.width;
    const int steps = static_cast<int>(std::lround(kPredictionSpan / kPredictionStep));
    for (int k = 0; k <= steps; ++k) {
      const double t = kPredictionStep * k;
      itp::scene::TimedPose p;
      p.t = now + t;  // scene time: the planner samples predictions from its request's `now`
      if (mode == Prediction::kGroundTruth) {
        const std::optional<Pose> q = pose_at(o, now + t);
        if (!q) {
          continue;  // appears later
        }
        p.x = q->x;
        p.y = q->y;
        p.heading = q->heading;
        p.v = v_now;
      } else {
        p.x = current->x + v_now * std::cos(current->heading) * t;
        p.y = current->y + v_now * std::sin(current->heading) * t;
        p.heading = current->heading;
        p.v = v_now;
      }
      if (!d.trajectory.push_back(p)) {
        res.error = "prediction longer than the planner holds";
        return res;
      }
    }
    if (d.trajectory.empty()) {
      continue;  // appears after the horizon
    }
    if (!out.dynamic_obstacles.push_back(d)) {
      res.error = "more dynamic obstacles in range than the planner holds";
      return res;
    }
  }
  res.ok = true;
  return res;
}

}  // namespace hil::sim
