#include "sim/closed_loop.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include <fmt/core.h>
#include <fmt/format.h>

#include "itp/planner/planner.hpp"
#include "sim/box_geometry.hpp"

namespace hil::sim {
namespace {

constexpr double kDefaultDuration = 12.0;  // [s]

template <class Cfg>
std::vector<TrajectoryPoint> to_track(const itp::planner::BasicPlan<Cfg>& plan) {
  std::vector<TrajectoryPoint> out;
  out.reserve(plan.trajectory.size());
  for (const auto& p : plan.trajectory) {
    out.push_back(TrajectoryPoint{p.t, p.x, p.y, p.heading, p.kappa, p.v, p.a});
  }
  return out;
}

// The true footprints of every obstacle present at t.
std::vector<OrientedBox> obstacle_boxes(const World& w, double t) {
  std::vector<OrientedBox> boxes;
  boxes.reserve(w.static_obstacles.size() + w.dynamic_obstacles.size());
  for (const auto& o : w.static_obstacles) boxes.push_back(obstacle_box(o));
  for (const auto& d : w.dynamic_obstacles) {
    if (const auto p = pose_at(d, t)) boxes.push_back(obstacle_box(d, *p));
  }
  return boxes;
}

// Velocities of the obstacles obstacle_boxes() lists, in the same order:
// statics stand, movers' from their motion over the last 0.1 s (0 in their
// first 0.1 s).
std::vector<Point2> obstacle_velocities(const World& w, double t) {
  constexpr double kDt = 0.1;
  std::vector<Point2> v(w.static_obstacles.size(), Point2{});
  for (const auto& d : w.dynamic_obstacles) {
    const auto p = pose_at(d, t);
    if (!p) continue;
    const auto before = pose_at(d, t - kDt);
    if (before) {
      v.push_back({(p->x - before->x) / kDt, (p->y - before->y) / kDt});
    } else {
      v.push_back({0.0, 0.0});
    }
  }
  return v;
}

// The simulator's view of the ego at one step (everything but the plan status).
StepSample observe(const World& w, const VehicleState& st, const VehicleParams& vp, double t) {
  StepSample x;
  x.t = t;
  const Pose pose{st.x, st.y, st.heading};
  x.ego = ego_box(pose, vp.length, vp.width, vp.wheelbase);
  x.ego_velocity = Point2{st.v * std::cos(st.heading), st.v * std::sin(st.heading)};
  x.obstacles = obstacle_boxes(w, t);
  x.obstacle_velocities = obstacle_velocities(w, t);
  const PolylineProjection pr = project_to_polyline(w.reference_line, st.x, st.y);
  x.progress_s = pr.s;
  x.lateral_offset = pr.l;
  x.heading_error = wrap_angle(st.heading - pr.heading);
  x.road_margin = road_margin(w.reference_line, w.road, x.ego);
  x.a_lon = st.a;
  x.a_lat = st.v * st.v * st.kappa(vp.wheelbase);
  return x;
}

struct Contact {
  std::optional<double> clearance;
  bool collision = false;
};

Contact contact(const StepSample& x) {
  Contact c;
  for (const auto& o : x.obstacles) {
    const double d = box_distance(x.ego, o);
    c.collision = c.collision || d <= 0.0;
    c.clearance = c.clearance ? std::min(*c.clearance, d) : d;
  }
  return c;
}

// Picks the cycles worth a look while the scene runs (see CycleSnapshot): the
// first problem (fallback / invalid input / link error), and the cycle before
// the first collision or, without one, the cycle before the smallest clearance.
template <class Cfg>
class SnapshotPicker {
 public:
  explicit SnapshotPicker(bool enabled) : enabled_(enabled) {}

  void remember(int cycle, double now, const itp::scene::BasicScene<Cfg>& scene) {
    if (!enabled_) return;
    history_.push_back({cycle, now, std::make_shared<const itp::scene::BasicScene<Cfg>>(scene)});
    while (history_.size() > 3) history_.pop_front();
  }
  void first_problem(int cycle, const std::string& why) {
    if (enabled_ && !problem_) problem_ = make(cycle, why);
  }
  // priority 2: collision (the first wins), 1: clearance (the smaller wins).
  void contact(int cycle, int priority, double value, const std::string& why) {
    if (!enabled_ || cycle < 0) return;
    if (priority < priority_ || (priority == priority_ && (priority == 2 || value >= value_))) return;
    if (auto shot = make(cycle, why)) {
      contact_ = std::move(shot);
      priority_ = priority;
      value_ = value;
    }
  }
  std::vector<CycleSnapshot> take() {
    std::vector<CycleSnapshot> out;
    if (problem_) out.push_back(std::move(*problem_));
    if (contact_ && (out.empty() || out.front().cycle != contact_->cycle)) out.push_back(std::move(*contact_));
    std::sort(out.begin(), out.end(), [](const CycleSnapshot& a, const CycleSnapshot& b) { return a.cycle < b.cycle; });
    return out;
  }

 private:
  struct Entry {
    int cycle;
    double now;
    SceneRef<Cfg> scene;
  };
  std::optional<CycleSnapshot> make(int cycle, const std::string& why) const {
    CycleSnapshot shot;
    shot.cycle = cycle;
    shot.why = why;
    for (const Entry& e : history_) {
      if (e.cycle == cycle - 1 || e.cycle == cycle) shot.scenes.emplace_back(e.now, AnySceneRef(e.scene));
      if (e.cycle == cycle) shot.now = e.now;
    }
    if (shot.scenes.empty()) return std::nullopt;
    return shot;
  }
  bool enabled_;
  std::deque<Entry> history_;
  std::optional<CycleSnapshot> problem_;
  std::optional<CycleSnapshot> contact_;
  int priority_ = 0;
  double value_ = std::numeric_limits<double>::infinity();
};

}  // namespace

template <class Cfg>
SceneRunResult run_scene(const World& world, BasicPlannerEndpoint<Cfg>& endpoint, const RunOptions& opt) {
  SceneRunResult result;
  SceneMetrics metrics(world.name, world.tags);
  VehicleParams vp;
  vp.wheelbase = world.ego.wheelbase;
  vp.length = world.ego.length;
  vp.width = world.ego.width;
  TrackingController controller(vp, opt.gains);
  VehicleState state = vehicle_from_ego(world.ego, vp);
  SnapshotPicker<Cfg> picker(opt.keep_snapshot);

  const double duration = opt.duration > 0 ? opt.duration : world.duration.value_or(kDefaultDuration);
  const double dt = opt.cycle > 0 ? opt.cycle : 0.1;
  const int n_cycles = std::max(0, static_cast<int>(std::lround(duration / dt)));
  auto scene = std::make_unique<itp::scene::BasicScene<Cfg>>();
  auto plan = std::make_unique<itp::planner::BasicPlan<Cfg>>();
  result.cycles.reserve(static_cast<std::size_t>(n_cycles));
  result.trace.reserve(static_cast<std::size_t>(n_cycles) + 1);

  // Contact at step k is the outcome of the plan of cycle k - 1.
  bool collided = false;
  auto judge_contact = [&](int step, const Contact& c) {
    if (c.collision && !collided) {
      collided = true;
      picker.contact(step - 1, 2, 0.0, fmt::format("first collision at t = {:.1f} s", step * dt));
    } else if (c.clearance) {
      picker.contact(step - 1, 1, *c.clearance, fmt::format("min clearance {:.2f} m at t = {:.1f} s", *c.clearance, step * dt));
    }
  };

  try {
    endpoint.reset();
    for (int k = 0; k <= n_cycles; ++k) {
      const double t = k * dt;
      StepSample sample = observe(world, state, vp, t);
      const Contact c = contact(sample);
      judge_contact(k, c);
      result.trace.push_back(svg::EgoTraceSample{t, Pose{state.x, state.y, state.heading}, state.v});
      if (k == n_cycles) {  // the final state: judged, no more planning
        metrics.add_step(sample);
        break;
      }

      CycleRecord rec;
      rec.t = t;
      rec.v = state.v;
      rec.a_lon = sample.a_lon;
      rec.a_lat = sample.a_lat;
      rec.clearance = c.clearance;
      rec.collision = c.collision;

      const EgoNow ego{state.x, state.y, state.heading, state.v, state.a, state.kappa(vp.wheelbase)};
      const ConvertResult conv = make_planner_scene(world, ego, t, opt.prediction, *scene);
      if (!conv.ok) {
        result.error = fmt::format("t = {:.1f} s: {}", t, conv.error);
        metrics.add_step(sample);
        metrics.set_crashed(result.error);
        break;
      }
      rec.left_out = conv.left_out();
      rec.reference_deviation_m = conv.reference_deviation_m;
      rec.boundary_narrowing_m = conv.boundary_narrowing_m;
      rec.stop_wall_lane = conv.stop_wall_lane;
      metrics.add_left_out(rec.left_out);
      picker.remember(k, t, *scene);
      const EndpointResult er = endpoint.plan(*scene, t, *plan);
      std::string problem;
      if (er.scene_mismatch) metrics.add_corrupt_scene();
      if (!er.ok) {
        metrics.add_link_error();
        // No fresh plan: follow the last valid one while it lasts, then stand
        // still at its end; without one, brake where the ego is.
        if (controller.has_plan() && !controller.braking()) {
          controller.stop_within_plan(opt.emergency_decel);
        } else {
          controller.emergency_brake(opt.emergency_decel);
        }
        rec.reason = er.error.empty() ? "link error" : er.error;
        problem = "link error: " + rec.reason;
      } else {
        rec.status = plan->status;
        sample.status = rec.status;
        if (rec.status == itp::PlanStatus::kFallback) {
          rec.reason = itp::planner::to_string(plan->fallback);
          if (plan->fallback == itp::planner::FallbackReason::kCollision && plan->collision_obstacle >= 0) {
            // What the rejected plan met, and when (the trace's reason only).
            rec.collision_with = fmt::format("{}@{:.1f}s", plan->collision_obstacle, plan->collision_time);
          }
          problem = "fallback: " + rec.reason;
        } else if (rec.status == itp::PlanStatus::kInvalidInput) {
          rec.reason = itp::scene::to_string(plan->invalid);
          problem = "invalid_input: " + rec.reason;
        }
        sample.reason = rec.reason;
        rec.iterations = plan->iterations;
        rec.work = plan->timing;
        for (const itp::planner::ObstacleDecision& d : plan->decisions) {
          const char side = d.lateral == itp::planner::LateralSide::kLeft    ? 'L'
                            : d.lateral == itp::planner::LateralSide::kRight ? 'R'
                                                                             : '-';
          rec.decisions += fmt::format("{}{}:{}/{}", rec.decisions.empty() ? "" : " ", d.obstacle, side,
                                       itp::speed::to_string(d.longitudinal));
        }
        if (rec.status != itp::PlanStatus::kInvalidInput) sample.iterations = plan->iterations;
        if (er.cycle_time_us >= 0) sample.cycle_time_us = rec.cycle_time_us = er.cycle_time_us;
        if (er.instructions >= 0) sample.instructions = rec.instructions = er.instructions;
        if (rec.status == itp::PlanStatus::kInvalidInput || plan->trajectory.empty()) {
          controller.emergency_brake(opt.emergency_decel);
        } else {
          std::vector<TrajectoryPoint> track = to_track(*plan);
          rec.v_plan = sample_plan(track, 1.0).v;
          rec.path_deviation = metrics.add_plan(t, track);
          rec.path_deviation_t = metrics.last_path_deviation_time();
          controller.set_plan(std::move(track), t);
        }
      }
      if (!problem.empty()) picker.first_problem(k, fmt::format("first {} at t = {:.1f} s", problem, t));
      metrics.add_step(sample);
      result.cycles.push_back(std::move(rec));
      controller.advance(state, t, dt);
    }
  } catch (const std::exception& e) {
    result.error = fmt::format("endpoint '{}': {}", endpoint.name(), e.what());
    metrics.set_crashed(result.error);
  }
  result.summary = metrics.summary();
  result.snapshots = picker.take();
  return result;
}

#define HIL_SIM_INSTANTIATE_RUN_SCENE(Cfg) \
  template SceneRunResult run_scene<Cfg>(const World&, BasicPlannerEndpoint<Cfg>&, const RunOptions&);
HIL_SIM_FOR_EACH_CONFIG(HIL_SIM_INSTANTIATE_RUN_SCENE)
#undef HIL_SIM_INSTANTIATE_RUN_SCENE

}  // namespace hil::sim
