#include "sim/commonroad_world.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "itp/config.hpp"
#include "sim/commonroad_route.hpp"
#include "sim/box_geometry.hpp"
#include "sim/commonroad_shape.hpp"

namespace hil::sim {
namespace {

namespace cr = formats::commonroad;

constexpr double kRouteBehind = 30.0;            // [m] of reference line wanted behind the ego
constexpr double kRouteBeyondRun = 200.0;        // [m] wanted beyond the ego's reach
constexpr double kFastestTraffic = 40.0;         // [m/s] the reach: duration at this speed
constexpr double kMaxRouteAhead = 5000.0;        // [m] of route wanted ahead, at most
constexpr double kMaxEgoKappa = 0.2;             // [1/m] the planner's default kappa_max
constexpr double kMinSpeedForKappa = 1.0;        // [m/s] below, yaw rate says nothing of the path
constexpr double kShiftAbove = 5.0e4;            // [m] coordinates beyond are shifted (planner: |x| <= 1e5)
constexpr int kMaxPredecessorsForLimit = 50;     // lanelets walked back for the limit in force

struct Frame {
  double dx = 0.0;  // subtracted from every x
  double dy = 0.0;
  Point2 operator()(const cr::Vec2& p) const { return {p.x - dx, p.y - dy}; }
};

const cr::PlanningProblem* pick_problem(const cr::Scenario& sc, const CommonRoadOptions& opt, CommonRoadImport& out) {
  if (sc.planning_problems.empty()) {
    out.error = "no <planningProblem>: the file gives no ego (initial state) to plan for";
    return nullptr;
  }
  if (!opt.planning_problem) {
    if (sc.planning_problems.size() > 1) {
      out.notes.push_back(fmt::format("{} planning problems: the first, {}, taken (--planning-problem ID picks another)",
                                      sc.planning_problems.size(), sc.planning_problems.front().id));
    }
    return &sc.planning_problems.front();
  }
  for (const cr::PlanningProblem& p : sc.planning_problems) {
    if (p.id == *opt.planning_problem) return &p;
  }
  std::string ids;
  for (const cr::PlanningProblem& p : sc.planning_problems) ids += fmt::format("{}{}", ids.empty() ? "" : ", ", p.id);
  out.error = fmt::format("no planningProblem with id {} (the file has: {})", *opt.planning_problem, ids);
  return nullptr;
}

// Speeds of the max-speed elements of the lanelet's signs (and a 2018b
// <speedLimit>): the lowest, if any.
std::optional<double> lanelet_limit(const cr::Lanelet& l, const std::map<long, const cr::TrafficSign*>& signs,
                                    std::string& error, std::vector<std::string>& notes) {
  std::optional<double> limit = l.speed_limit;
  for (long ref : l.traffic_signs) {
    const auto it = signs.find(ref);
    if (it == signs.end()) {
      if (error.empty()) error = fmt::format("line {}: lanelet {}: trafficSignRef {} does not exist", l.line, l.id, ref);
      return std::nullopt;
    }
    for (const cr::TrafficSignElement& e : it->second->elements) {
      if (!is_max_speed_sign(e.sign_id)) continue;
      double v = 0;
      const std::string text = e.values.empty() ? std::string() : e.values.front();
      char* end = nullptr;
      v = std::strtod(text.c_str(), &end);
      if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v) || v <= 0) {
        notes.push_back(fmt::format("line {}: trafficSign {}: max speed '{}' is not a speed; sign ignored",
                                    it->second->line, it->second->id, text));
        continue;
      }
      limit = limit ? std::min(*limit, v) : v;
    }
  }
  return limit;
}

// The lowest max speed along the route ahead, and the one in force at the ego
// (its lanelet's, else the nearest one behind it through predecessors).
std::optional<double> route_speed_limit(const cr::Scenario& sc, const LaneRoute& route, std::string& error,
                                        std::vector<std::string>& notes, std::string& source) {
  std::map<long, const cr::TrafficSign*> signs;
  for (const cr::TrafficSign& s : sc.traffic_signs) signs[s.id] = &s;
  std::map<long, const cr::Lanelet*> lanelets;
  for (const cr::Lanelet& l : sc.lanelets) lanelets[l.id] = &l;
  std::optional<double> limit;
  for (std::size_t i = route.ego_index; i < route.lanelets.size(); ++i) {
    const std::optional<double> v = lanelet_limit(*lanelets.at(route.lanelets[i]), signs, error, notes);
    if (v && (!limit || *v < *limit)) {
      limit = v;
      source = fmt::format("lanelet {}", route.lanelets[i]);
    }
  }
  if (!error.empty()) return std::nullopt;
  // In force at the ego when its own lanelet has no sign: the nearest behind it.
  const cr::Lanelet* l = lanelets.at(route.lanelets[route.ego_index]);
  if (l->speed_limit || !l->traffic_signs.empty()) {
    std::vector<std::string> repeated;  // its signs were read (and noted) above
    if (lanelet_limit(*l, signs, error, repeated)) return limit;
  }
  for (int k = 0; k < kMaxPredecessorsForLimit && !l->predecessors.empty(); ++k) {
    const auto it = lanelets.find(l->predecessors.front());
    if (it == lanelets.end()) break;
    l = it->second;
    const std::optional<double> v = lanelet_limit(*l, signs, error, notes);
    if (v) {
      if (!limit || *v < *limit) {
        limit = v;
        source = fmt::format("lanelet {} (behind the ego)", l->id);
      }
      break;
    }
  }
  return limit;
}

double finite_difference_speed(const std::vector<cr::State>& states, std::size_t i, double dt) {
  if (states.size() < 2) return 0.0;
  const std::size_t a = i + 1 < states.size() ? i : i - 1;
  const cr::State& p = states[a];
  const cr::State& q = states[a + 1];
  const double t = static_cast<double>(q.time_step - p.time_step) * dt;
  return std::hypot(q.position.x - p.position.x, q.position.y - p.position.y) / t;
}

bool map_obstacles(const cr::Scenario& sc, const Frame& frame, World& w, CommonRoadImport& out) {
  int uncertain = 0;
  for (const cr::Obstacle& o : sc.obstacles) {
    if (o.id < std::numeric_limits<std::int32_t>::min() || o.id > std::numeric_limits<std::int32_t>::max()) {
      out.error = fmt::format("line {}: obstacle {}: the id does not fit scene/1's integer ids", o.line, o.id);
      return false;
    }
    const LocalBox box = bounding_box(o.shape, o.dynamic);
    const std::string kind = o.type.empty() ? "" : o.type;
    if (!o.dynamic) {
      const Point2 p = frame(o.initial.position);
      const Pose c = place(box, p.x, p.y, o.initial.orientation);
      w.static_obstacles.push_back({static_cast<int>(o.id), c.x, c.y, c.heading, box.length, box.width, kind});
      uncertain += o.initial.uncertain ? 1 : 0;
      continue;
    }
    std::vector<cr::State> states{o.initial};
    states.insert(states.end(), o.trajectory.begin(), o.trajectory.end());
    DynamicObstacle d;
    d.id = static_cast<int>(o.id);
    d.length = box.length;
    d.width = box.width;
    d.kind = kind;
    bool any_uncertain = false;
    for (std::size_t i = 0; i < states.size(); ++i) {
      const cr::State& s = states[i];
      const Point2 p = frame(s.position);
      const Pose c = place(box, p.x, p.y, s.orientation);
      const double v = s.velocity.value_or(finite_difference_speed(states, i, sc.time_step));
      d.trajectory.push_back({static_cast<double>(s.time_step) * sc.time_step, c.x, c.y, c.heading, v});
      any_uncertain = any_uncertain || s.uncertain;
    }
    uncertain += any_uncertain ? 1 : 0;
    w.dynamic_obstacles.push_back(std::move(d));
  }
  if (uncertain > 0) {
    out.notes.push_back(fmt::format("{} obstacles have uncertain states (intervals, position regions): read as the "
                                    "midpoints and region centres",
                                    uncertain));
  }
  return true;
}

// The run's length: the goal's time interval end or the last obstacle time
// step, whichever is later, at most kCommonRoadMaxDuration.
double scenario_duration(const cr::Scenario& sc, const cr::PlanningProblem& p, std::vector<std::string>& notes) {
  long last = 0;
  for (const cr::GoalState& g : p.goals) last = std::max(last, g.time_end.value_or(0));
  for (const cr::Obstacle& o : sc.obstacles) {
    last = std::max(last, o.trajectory.empty() ? o.initial.time_step : o.trajectory.back().time_step);
  }
  double d = static_cast<double>(last) * sc.time_step;
  if (d <= 0.0) {
    notes.push_back(fmt::format("no goal time and no obstacle trajectory: duration {} s", kCommonRoadDefaultDuration));
    d = kCommonRoadDefaultDuration;
  }
  if (d > kCommonRoadMaxDuration) {
    notes.push_back(fmt::format("the scenario lasts {:.1f} s: cut to {} s (--duration sets it)", d, kCommonRoadMaxDuration));
    d = kCommonRoadMaxDuration;
  }
  return d;
}

// The lane map of the lane-following prediction (World::lanes): every vehicle
// lanelet (not a sidewalk, crosswalk or bicycle lane) with its centre line,
// bounds and successors, and its active traffic lights with the stop line
// (its points' midpoint projected onto the centre line; without points the
// lanelet's end).
void map_lanes(const cr::Scenario& sc, World& w, std::vector<std::string>& notes) {
  std::map<long, const cr::TrafficLight*> lights;
  for (const cr::TrafficLight& t : sc.traffic_lights) lights.emplace(t.id, &t);
  int with_lights = 0;
  int inactive = 0;
  std::vector<long> missing;
  for (const cr::Lanelet& l : sc.lanelets) {
    const bool vehicle = std::none_of(l.types.begin(), l.types.end(), [](const std::string& t) {
      return t == "sidewalk" || t == "crosswalk" || t == "bicycleLane";
    });
    if (!vehicle) continue;
    Lane lane;
    lane.id = l.id;
    for (const Point2& p : lanelet_centre(l)) {  // no zero-length segments: they have no direction
      if (lane.centre.empty() || std::hypot(p.x - lane.centre.back().x, p.y - lane.centre.back().y) > 0.01) {
        lane.centre.push_back(p);
      }
    }
    for (const cr::Vec2& p : l.left_bound) lane.left.push_back({p.x, p.y});
    for (const cr::Vec2& p : l.right_bound) lane.right.push_back({p.x, p.y});
    lane.successors = l.successors;
    if (lane.centre.size() < 2) continue;
    for (long ref : l.traffic_lights) {
      const auto it = lights.find(ref);
      if (it == lights.end()) {
        missing.push_back(ref);
        continue;
      }
      if (!it->second->active) {
        ++inactive;
        continue;
      }
      TrafficLightCycle c;
      c.time_offset = static_cast<double>(it->second->time_offset) * sc.time_step;
      for (const cr::TrafficLightPhase& ph : it->second->cycle) {
        c.cycle.push_back({ph.color, static_cast<double>(ph.duration) * sc.time_step});
      }
      lane.traffic_lights.push_back(std::move(c));
    }
    if (!lane.traffic_lights.empty()) {
      ++with_lights;
      const std::vector<double> arc = polyline_arc_lengths(lane.centre);
      lane.stop_s = arc.back();
      if (l.stop_line.size() >= 2) {
        const cr::Vec2& a = l.stop_line.front();
        const cr::Vec2& b = l.stop_line.back();
        lane.stop_s = std::clamp(project_to_polyline(lane.centre, 0.5 * (a.x + b.x), 0.5 * (a.y + b.y)).s, 0.0, arc.back());
      }
    }
    w.lanes.push_back(std::move(lane));
  }
  if (!sc.traffic_lights.empty()) {
    notes.push_back(fmt::format("{} traffic lights on {} lanes: the lane-following prediction stops traffic at their "
                                "stop lines{}",
                                sc.traffic_lights.size(), with_lights,
                                inactive > 0 ? fmt::format(" ({} references to inactive lights left out)", inactive) : ""));
  }
  if (!missing.empty()) {
    notes.push_back(fmt::format("{} trafficLightRef to lights the file does not have (first: {}): left out",
                                missing.size(), missing.front()));
  }
}

}  // namespace

bool is_max_speed_sign(const std::string& id) { return id == "274" || id == "274.1" || id == "R2-1" || id == "r301"; }

CommonRoadImport map_commonroad(const cr::Scenario& sc, const CommonRoadOptions& opt) {
  CommonRoadImport out;
  for (const std::string& s : sc.ignored) out.notes.push_back(s);
  const cr::PlanningProblem* problem = pick_problem(sc, opt, out);
  if (!problem) return out;
  const std::string where = fmt::format("line {}: planningProblem {}: initialState", problem->line, problem->id);
  const cr::State& init = problem->initial;
  if (!init.velocity) {
    out.error = where + ": <velocity> missing";
    return out;
  }
  if (*init.velocity < 0.0) {
    out.error = fmt::format("{}: velocity {} m/s: driving backwards is not supported", where, *init.velocity);
    return out;
  }
  if (init.uncertain) out.notes.push_back(where + ": uncertain (intervals or a region): read as its midpoint");

  Frame frame;
  if (std::fabs(init.position.x) > kShiftAbove || std::fabs(init.position.y) > kShiftAbove) {
    frame.dx = 1000.0 * std::round(init.position.x / 1000.0);
    frame.dy = 1000.0 * std::round(init.position.y / 1000.0);
    out.notes.push_back(fmt::format("coordinates shifted by ({}, {}) m: the planner takes |x|, |y| <= {} m", -frame.dx,
                                    -frame.dy, static_cast<double>(itp::config::kMaxCoordinate)));
  }
  // The lanelets in the shifted frame.
  cr::Scenario shifted = sc;
  for (cr::Lanelet& l : shifted.lanelets) {
    for (auto* bound : {&l.left_bound, &l.right_bound, &l.stop_line}) {
      for (cr::Vec2& p : *bound) p = {p.x - frame.dx, p.y - frame.dy};
    }
  }

  World w;
  w.name = sc.benchmark_id.empty() ? std::string("commonroad") : sc.benchmark_id;
  if (sc.planning_problems.size() > 1) w.name += fmt::format("-pp{}", problem->id);
  w.tags = {"commonroad", "commonroad:" + (sc.version.empty() ? std::string("?") : sc.version),
            fmt::format("planning_problem:{}", problem->id)};
  const double duration = opt.duration.value_or(scenario_duration(sc, *problem, out.notes));
  w.duration = duration;

  // Ego: CommonRoad's position is the vehicle's centre; scene/1's is the rear
  // axle, with the box centre half a wheelbase ahead of it.
  const Point2 centre = frame(init.position);
  const double heading = wrap_angle(init.orientation);
  w.ego.length = kCommonRoadEgoLength;
  w.ego.width = kCommonRoadEgoWidth;
  w.ego.wheelbase = kCommonRoadEgoWheelbase;
  w.ego.x = centre.x - 0.5 * w.ego.wheelbase * std::cos(heading);
  w.ego.y = centre.y - 0.5 * w.ego.wheelbase * std::sin(heading);
  w.ego.heading = heading;
  w.ego.v = *init.velocity;
  w.ego.a = init.acceleration.value_or(0.0);
  if (init.yaw_rate && w.ego.v >= kMinSpeedForKappa) {
    const double kappa = *init.yaw_rate / w.ego.v;
    w.ego.kappa = std::clamp(kappa, -kMaxEgoKappa, kMaxEgoKappa);
    if (w.ego.kappa != kappa) out.notes.push_back(fmt::format("{}: curvature {:.3f} 1/m clamped to {}", where, kappa, w.ego.kappa));
  }

  // Road: the ego's lanelet and the route through its successors.
  RouteOptions ro;
  ro.opposite_lanes = opt.opposite_lanes;
  ro.length_behind = kRouteBehind;
  ro.length_ahead = std::min(kMaxRouteAhead, kRouteBeyondRun + kFastestTraffic * duration);
  for (const cr::GoalState& g : problem->goals) {
    ro.goal_lanelets.insert(ro.goal_lanelets.end(), g.lanelets.begin(), g.lanelets.end());
    for (const cr::Vec2& c : g.area_centres) {
      const Point2 p = frame(c);
      for (const cr::Lanelet& l : shifted.lanelets) {
        if (polygon_contains(lanelet_polygon(l), p)) ro.goal_lanelets.push_back(l.id);
      }
    }
  }
  const RouteResult route = build_route(shifted, Pose{centre.x, centre.y, heading}, ro);
  if (!route.route) {
    out.error = route.error.rfind("line ", 0) == 0 ? route.error : fmt::format("{}: {}", where, route.error);
    return out;
  }
  const LaneRoute& r = *route.route;
  for (const std::string& n : r.notes) out.notes.push_back(n);
  const double route_length = polyline_arc_lengths(r.reference_line).back();
  if (route_length < static_cast<double>(itp::config::kMinReferenceLineLength)) {
    out.error = fmt::format("lanelet {}: the route from the ego's lanelet is {:.1f} m long; the planner needs {} m",
                            r.lanelets[r.ego_index], route_length,
                            static_cast<double>(itp::config::kMinReferenceLineLength));
    return out;
  }
  w.reference_line = r.reference_line;
  w.road.left_boundary = r.left;
  w.road.right_boundary = r.right;
  w.road.target_lane_offset = 0.0;
  const double min_w = static_cast<double>(itp::config::kMinLaneWidth);
  const double max_w = static_cast<double>(itp::config::kMaxLaneWidth);
  w.road.lane_width = std::clamp(r.lane_width, min_w, max_w);
  if (w.road.lane_width != r.lane_width) {
    out.notes.push_back(fmt::format("lanelet {}: lane width {:.2f} m clamped to {:.2f} m (the planner's range)",
                                    r.lanelets[r.ego_index], r.lane_width, w.road.lane_width));
  }
  out.notes.push_back(fmt::format("route: {} lanelets, {:.0f} m, ego in lanelet {}; road: {} lanelets{}", r.lanelets.size(),
                                  route_length, r.lanelets[r.ego_index], r.road_lanelets.size(),
                                  opt.opposite_lanes ? " (with opposite lanes)" : ""));

  // Speed limit: signs, else the default (not below the ego's own speed).
  std::string error;
  std::string source;
  const std::optional<double> signed_limit = route_speed_limit(shifted, r, error, out.notes, source);
  if (!error.empty()) {
    out.error = error;
    return out;
  }
  if (opt.speed_limit) {
    w.road.speed_limit = *opt.speed_limit;
  } else if (signed_limit) {
    w.road.speed_limit = *signed_limit;
    out.notes.push_back(fmt::format("speed limit {:.2f} m/s from the max-speed sign of {}", *signed_limit, source));
  }
  if (!map_obstacles(sc, frame, w, out)) return out;
  map_lanes(shifted, w, out.notes);
  if (!opt.speed_limit && !signed_limit) {
    // No sign: 50 km/h, but not below the speeds the scenario starts with.
    double fastest = w.ego.v;
    for (const DynamicObstacle& d : w.dynamic_obstacles) fastest = std::max(fastest, d.trajectory.front().v);
    w.road.speed_limit = std::max(kCommonRoadDefaultSpeedLimit, fastest);
    out.notes.push_back(fmt::format("no max-speed sign on the route: speed limit {:.2f} m/s (the default: 50 km/h, "
                                    "or the fastest initial speed of the ego and the traffic)",
                                    w.road.speed_limit));
  }
  out.world = std::move(w);
  return out;
}

CommonRoadImport import_commonroad(std::string_view xml, const CommonRoadOptions& opt) {
  try {
    cr::ReadOptions ro;
    ro.drop_set_based = opt.drop_set_based;
    const cr::ReadResult read = cr::read_commonroad(xml, ro);
    if (!read) {
      CommonRoadImport out;
      out.error = read.error;
      return out;
    }
    return map_commonroad(*read.scenario, opt);
  } catch (const std::exception& e) {  // allocation failure; the mapping itself does not throw
    CommonRoadImport out;
    out.error = fmt::format("cannot import the scenario: {}", e.what());
    return out;
  }
}

}  // namespace hil::sim
