#include "sim/scene_convert.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

#include "itp/configurations.hpp"
#include "sim/box_geometry.hpp"
#include "sim/ego_traffic_lights.hpp"
#include "sim/lane_prediction.hpp"
#include "sim/road_resampling.hpp"

namespace hil::sim {
namespace {

constexpr double kBehind = 40.0;           // [m] of reference line kept behind the ego (rear traffic)
constexpr double kAheadBeyondPath = 20.0;  // [m] kept ahead beyond the longest SL horizon
constexpr double kRelevantRange = 160.0;   // [m] obstacles farther from the ego are left out
constexpr double kRelevanceStep = 0.5;     // [s] sampling of the relevance rule
constexpr double kRelevanceBraking = 4.0;  // [m/s^2] the braking ego of the relevance rule

template <class Cfg>
void copy_boundary(const Boundary& from, double s0, double length, double margin, EdgeSide side,
                   itp::scene::BasicBoundary<Cfg>& to, double& narrowing) {
  const double inwards = side == EdgeSide::kLeft ? -margin : margin;
  to.table.clear();
  if (from.is_constant()) {
    to.offset = from.constant + inwards;
    narrowing = std::max(narrowing, margin);
    return;
  }
  const EdgeFit fit = fit_edge_inside(from.knots, s0, s0 + length, Cfg::kMaxBoundaryPoints, side);
  narrowing = std::max(narrowing, fit.max_narrowing + margin);
  to.offset = fit.knots.front().l + inwards;
  if (fit.knots.size() < 2) return;  // a zero-length window: the constant is the edge
  for (const Boundary::Knot& k : fit.knots) {
    if (!to.table.push_back({k.s - s0, k.l + inwards})) break;  // fitted to the capacity: never taken
  }
}

// The ego's footprint every kRelevanceStep from now, moving along the
// reference line at its current lateral offset, in two ways: at its current
// speed, and braking at kRelevanceBraking to a stop (what a fallback does; it
// makes the traffic close behind relevant).
struct EgoSweep {
  std::vector<OrientedBox> cruising;
  std::vector<OrientedBox> braking;
};

EgoSweep ego_sweep(const World& w, const std::vector<double>& arc, const EgoNow& ego, double horizon) {
  EgoSweep sweep;
  const PolylineProjection p = project_to_polyline(w.reference_line, ego.x, ego.y);
  const int steps = static_cast<int>(std::lround(horizon / kRelevanceStep));
  const double v = std::max(0.0, ego.v);
  for (int k = 0; k <= steps; ++k) {
    const double t = kRelevanceStep * k;
    const double t_stop = std::min(t, v / kRelevanceBraking);
    const double braked = v * t_stop - 0.5 * kRelevanceBraking * t_stop * t_stop;
    const Pose now{ego.x, ego.y, ego.heading};
    const Pose cruise = k == 0 ? now : polyline_pose(w.reference_line, arc, p.s + v * t, p.l);
    const Pose brake = k == 0 ? now : polyline_pose(w.reference_line, arc, p.s + braked, p.l);
    sweep.cruising.push_back(ego_box(cruise, w.ego.length, w.ego.width, w.ego.wheelbase));
    sweep.braking.push_back(ego_box(brake, w.ego.length, w.ego.width, w.ego.wheelbase));
  }
  return sweep;
}

template <class Item>
struct Candidate {
  Relevance relevance;
  Item item;
};

template <class Item, class Vec>
int keep_most_relevant(std::vector<Candidate<Item>>& candidates, Vec& out) {
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate<Item>& a, const Candidate<Item>& b) { return a.relevance < b.relevance; });
  int left_out = 0;
  for (Candidate<Item>& c : candidates) {
    if (!out.push_back(c.item)) ++left_out;
  }
  return left_out;
}

bool is_ahead(const EgoNow& ego, double x, double y) {
  return (x - ego.x) * std::cos(ego.heading) + (y - ego.y) * std::sin(ego.heading) >= 0.0;
}

}  // namespace

bool Relevance::operator<(const Relevance& o) const {
  return std::tuple(approach_m, !ahead, distance_now_m, id) < std::tuple(o.approach_m, !o.ahead, o.distance_now_m, o.id);
}

const char* prediction_name(Prediction p) {
  switch (p) {
    case Prediction::kGroundTruth: return "truth";
    case Prediction::kConstantVelocity: return "cv";
    case Prediction::kLane: return "lane";
  }
  return "?";
}

EgoNow ego_at_start(const World& w) {
  return EgoNow{w.ego.x, w.ego.y, w.ego.heading, w.ego.v, w.ego.a, w.ego.kappa};
}

template <class Cfg>
ConvertResult make_planner_scene(const World& w, const EgoNow& ego, double now, Prediction mode,
                                 itp::scene::BasicScene<Cfg>& out) {
  constexpr double kAhead = static_cast<double>(Cfg::kMaxPathLength) + kAheadBeyondPath;
  constexpr double kHorizon = static_cast<double>(Cfg::kSpeedHorizon);
  ConvertResult res;
  out = itp::scene::BasicScene<Cfg>{};
  if (w.reference_line.size() < 2) {
    res.error = "reference line has fewer than 2 points";
    return res;
  }
  // Reference-line window [s_ego - kBehind, s_ego + kAhead], resampled to Cfg.
  const std::vector<double> arc = polyline_arc_lengths(w.reference_line);
  const double s_ego = project_to_polyline(w.reference_line, ego.x, ego.y).s;
  std::size_t first = 0;
  while (first + 1 < w.reference_line.size() && arc[first + 1] <= s_ego - kBehind) {
    ++first;
  }
  std::size_t last = first;
  while (last + 1 < w.reference_line.size() && arc[last + 1] <= s_ego + kAhead) {
    ++last;
  }
  last = std::max(last, std::min(first + 1, w.reference_line.size() - 1));  // >= 2 points
  const std::span<const Point2> window(w.reference_line.data() + first, last - first + 1);
  const PolylineFit line = simplify_polyline(window, Cfg::kMaxReferencePoints);
  for (const Point2& p : line.points) {
    if (!out.reference_line.push_back({p.x, p.y})) break;  // fitted to the capacity: never taken
  }
  res.window_s0 = arc[first];
  res.reference_deviation_m = line.max_deviation;

  out.road.lane_width = w.road.lane_width;
  out.road.target_lane_offset = w.road.target_lane_offset;
  out.road.speed_limit = w.road.speed_limit;
  const double length = arc[last] - arc[first];
  copy_boundary(w.road.left_boundary, res.window_s0, length, line.max_deviation, EdgeSide::kLeft, out.road.left,
                res.boundary_narrowing_m);
  copy_boundary(w.road.right_boundary, res.window_s0, length, line.max_deviation, EdgeSide::kRight, out.road.right,
                res.boundary_narrowing_m);
  out.ego.state = {ego.x, ego.y, ego.heading, ego.v, ego.a, ego.kappa};
  out.ego.geometry = {w.ego.length, w.ego.width, w.ego.wheelbase};

  const EgoSweep sweep = ego_sweep(w, arc, ego, kHorizon);
  auto approach = [&](auto&& box_at) {
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < sweep.cruising.size(); ++k) {
      if (const std::optional<OrientedBox> b = box_at(kRelevanceStep * static_cast<double>(k))) {
        d = std::min({d, box_distance(*b, sweep.cruising[k]), box_distance(*b, sweep.braking[k])});
      }
    }
    return d;
  };

  std::vector<Candidate<itp::scene::StaticObstacle>> statics;
  for (const StaticObstacle& o : w.static_obstacles) {
    const double distance = std::hypot(o.x - ego.x, o.y - ego.y);
    if (distance > kRelevantRange) continue;
    const OrientedBox box = obstacle_box(o);
    const double d = approach([&](double) { return std::optional<OrientedBox>(box); });
    statics.push_back({{d, is_ahead(ego, o.x, o.y), distance, o.id}, {o.id, o.x, o.y, o.heading, o.length, o.width}});
  }
  // The ego's own red light: a wall across the road, the most relevant of all.
  const LaneMap lanes(w.lanes);
  if (const std::optional<StopWall> wall = ego_stop_wall(w, lanes, arc, ego, now)) {
    const StaticObstacle& o = wall->box;
    statics.push_back({{0.0, true, 0.0, o.id}, {o.id, o.x, o.y, o.heading, o.length, o.width}});
    res.stop_wall_lane = wall->lane;
  }
  res.static_left_out = keep_most_relevant(statics, out.static_obstacles);

  std::vector<Candidate<itp::scene::BasicDynamicObstacle<Cfg>>> dynamics;
  // Every 0.1 s, or the smallest multiple of it whose samples over the
  // horizon (+0.5 s) Cfg holds (the road configuration: 0.2 s).
  const double step = prediction_step<Cfg>();
  const int steps = static_cast<int>(std::lround((kHorizon + 0.5) / step));
  std::vector<double> times;
  for (int k = 0; k <= steps; ++k) times.push_back(step * k);
  for (const DynamicObstacle& o : w.dynamic_obstacles) {
    const std::optional<Pose> current = pose_at(o, now);
    const double v_now = [&] {
      for (std::size_t i = 0; i + 1 < o.trajectory.size(); ++i) {
        if (o.trajectory[i + 1].t >= now) return o.trajectory[i].v;
      }
      return o.trajectory.back().v;
    }();
    if (mode != Prediction::kGroundTruth && !current) {
      continue;  // not perceived yet
    }
    if (current && std::hypot(current->x - ego.x, current->y - ego.y) > kRelevantRange) {
      continue;
    }
    // Along its lane (not a pedestrian's), else straight on.
    std::optional<std::vector<Pose>> along_lane;
    if (mode == Prediction::kLane && o.kind != "pedestrian") {
      along_lane = predict_along_lanes(lanes, *current, v_now, times, now, 0.5 * o.length);
    }
    itp::scene::BasicDynamicObstacle<Cfg> d;
    d.id = o.id;
    d.length = o.length;
    d.width = o.width;
    for (int k = 0; k <= steps; ++k) {
      const double t = step * k;
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
      } else if (along_lane) {
        const Pose& q = (*along_lane)[static_cast<std::size_t>(k)];
        p.x = q.x;
        p.y = q.y;
        p.heading = q.heading;
        p.v = v_now;
      } else {
        p.x = current->x + v_now * std::cos(current->heading) * t;
        p.y = current->y + v_now * std::sin(current->heading) * t;
        p.heading = current->heading;
        p.v = v_now;
      }
      if (!d.trajectory.push_back(p)) break;  // the prediction is as long as Cfg holds
    }
    if (d.trajectory.empty()) {
      continue;  // appears after the horizon
    }
    const double distance = current ? std::hypot(current->x - ego.x, current->y - ego.y)
                                    : std::hypot(d.trajectory[0].x - ego.x, d.trajectory[0].y - ego.y);
    const bool ahead = current ? is_ahead(ego, current->x, current->y) : is_ahead(ego, d.trajectory[0].x, d.trajectory[0].y);
    const double approach_m = approach([&](double t) -> std::optional<OrientedBox> {
      for (const itp::scene::TimedPose& p : d.trajectory) {
        if (p.t >= now + t - 1e-9) return OrientedBox{p.x, p.y, p.heading, o.length, o.width};
      }
      return std::nullopt;
    });
    dynamics.push_back({{approach_m, ahead, distance, o.id}, d});
  }
  res.dynamic_left_out = keep_most_relevant(dynamics, out.dynamic_obstacles);
  res.ok = true;
  return res;
}

#define HIL_SIM_INSTANTIATE_CONVERT(Cfg)                                                                  \
  template ConvertResult make_planner_scene<Cfg>(const World&, const EgoNow&, double, Prediction, \
                                                 itp::scene::BasicScene<Cfg>&);
ITP_FOR_EACH_CONFIG(HIL_SIM_INSTANTIATE_CONVERT)
#undef HIL_SIM_INSTANTIATE_CONVERT

}  // namespace hil::sim
