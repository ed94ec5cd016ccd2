#include "sim/closed_loop.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <fmt/core.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "itp/planner/planner.hpp"
#include "sim/box_geometry.hpp"
#include "sim/inproc_endpoint.hpp"
#include "link/fault_injection.hpp"
#include "sim/link_endpoint.hpp"
#include "sim/plan_plots.hpp"
#include "sim/scene_files.hpp"
#include "sim/scene_generator.hpp"

namespace hil::sim {
namespace {

using nlohmann::json;

constexpr double kDefaultDuration = 12.0;  // [s]

PlanStatus to_sim_status(itp::PlanStatus s) {
  switch (s) {
    case itp::PlanStatus::kOk: return PlanStatus::kOk;
    case itp::PlanStatus::kFallback: return PlanStatus::kFallback;
    case itp::PlanStatus::kInvalidInput: return PlanStatus::kInvalidInput;
  }
  return PlanStatus::kInvalidInput;
}

std::vector<TrajectoryPoint> to_track(const itp::planner::Plan& plan) {
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
class SnapshotPicker {
 public:
  explicit SnapshotPicker(bool enabled) : enabled_(enabled) {}

  void remember(int cycle, double now, const itp::scene::Scene& scene) {
    if (!enabled_) return;
    history_.push_back({cycle, now, std::make_shared<const itp::scene::Scene>(scene)});
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
    std::shared_ptr<const itp::scene::Scene> scene;
  };
  std::optional<CycleSnapshot> make(int cycle, const std::string& why) const {
    CycleSnapshot shot;
    shot.cycle = cycle;
    shot.why = why;
    for (const Entry& e : history_) {
      if (e.cycle == cycle - 1 || e.cycle == cycle) shot.scenes.emplace_back(e.now, e.scene);
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

SceneRunResult run_scene(const World& world, PlannerEndpoint& endpoint, const RunOptions& opt) {
  SceneRunResult result;
  SceneMetrics metrics(world.name, world.tags);
  VehicleParams vp;
  vp.wheelbase = world.ego.wheelbase;
  vp.length = world.ego.length;
  vp.width = world.ego.width;
  TrackingController controller(vp, opt.gains);
  VehicleState state = vehicle_from_ego(world.ego, vp);
  SnapshotPicker picker(opt.keep_snapshot);

  const double duration = opt.duration > 0 ? opt.duration : world.duration.value_or(kDefaultDuration);
  const double dt = opt.cycle > 0 ? opt.cycle : 0.1;
  const int n_cycles = std::max(0, static_cast<int>(std::lround(duration / dt)));
  auto scene = std::make_unique<itp::scene::Scene>();
  auto plan = std::make_unique<itp::planner::Plan>();
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
        rec.status = to_sim_status(plan->status);
        sample.status = rec.status;
        if (rec.status == PlanStatus::kFallback) {
          rec.reason = itp::planner::to_string(plan->fallback);
          if (plan->fallback == itp::planner::FallbackReason::kCollision && plan->collision_obstacle >= 0) {
            // What the rejected plan met, and when (the trace's reason only).
            rec.collision_with = fmt::format("{}@{:.1f}s", plan->collision_obstacle, plan->collision_time);
          }
          problem = "fallback: " + rec.reason;
        } else if (rec.status == PlanStatus::kInvalidInput) {
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
        if (rec.status != PlanStatus::kInvalidInput) sample.iterations = plan->iterations;
        if (er.cycle_time_us >= 0) sample.cycle_time_us = rec.cycle_time_us = er.cycle_time_us;
        if (er.instructions >= 0) sample.instructions = rec.instructions = er.instructions;
        if (rec.status == PlanStatus::kInvalidInput || plan->trajectory.empty()) {
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

// ---------------------------------------------------------------------------
// Plots

std::string scene_run_svg(const World& world, const SceneRunResult& r) {
  std::vector<std::string> parts;
  const SceneSummary& s = r.summary;
  std::string title = fmt::format("{}: collision {}, road departure {}, fallbacks {}, min clearance {}", world.name,
                                  s.collided() ? "YES" : "no", s.departed() ? "YES" : "no", s.fallbacks,
                                  s.min_clearance_m ? fmt::format("{:.2f} m", *s.min_clearance_m) : std::string("-"));
  std::string tags;
  for (const auto& tag : world.tags) tags += " " + tag;
  if (title.size() + tags.size() < 150) title += " —" + tags;
  svg::XyPlotOptions xy;
  xy.title = title;
  xy.t_end = r.trace.empty() ? -1.0 : r.trace.back().t;
  parts.push_back(plot_scene_xy(world, r.trace, xy));

  // Speed over time, with the limit and the plan's speed 1 s ahead; statuses as markers below.
  std::vector<svg::Series> speed(3);
  speed[0].name = "ego v";
  speed[1].name = "plan v(t + 1 s)";
  speed[1].dashed = true;
  speed[2].name = "speed limit";
  speed[2].colour = "#888888";
  speed[2].dashed = true;
  for (const auto& e : r.trace) speed[0].points.push_back({e.t, e.v});
  for (const auto& c : r.cycles) {
    if (c.status == PlanStatus::kOk || c.status == PlanStatus::kFallback) speed[1].points.push_back({c.t, c.v_plan});
  }
  const double t_end = r.trace.empty() ? 0.0 : r.trace.back().t;
  speed[2].points = {{0.0, world.road.speed_limit}, {t_end, world.road.speed_limit}};
  parts.push_back(plot_line_chart("speed", "t [s]", "v [m/s]", speed));

  std::vector<svg::Series> other(4);
  other[0].name = "min clearance [m] (clipped at 10)";
  other[1].name = "a_lon [m/s²]";
  other[2].name = "a_lat [m/s²]";
  other[3].name = "plan status (0 ok, 1 fallback, 2 invalid input, 3 link error)";
  other[3].colour = "#000000";
  other[3].dashed = true;
  for (const auto& c : r.cycles) {
    if (c.clearance) other[0].points.push_back({c.t, std::min(10.0, *c.clearance)});
    other[1].points.push_back({c.t, c.a_lon});
    other[2].points.push_back({c.t, c.a_lat});
    const double code = c.status == PlanStatus::kOk         ? 0.0
                        : c.status == PlanStatus::kFallback ? 1.0
                        : c.status == PlanStatus::kInvalidInput ? 2.0
                                                                : 3.0;
    other[3].points.push_back({c.t, code});
    other[3].points.push_back({c.t + 0.1, code});
  }
  parts.push_back(plot_line_chart("clearance, accelerations, plan status", "t [s]", "", other));

  for (const CycleSnapshot& shot : r.snapshots) {
    if (shot.scenes.empty()) continue;
    // Re-plan the chosen cycle in-process (after its predecessor, for stitching).
    auto planner = std::make_unique<itp::planner::Planner>();
    auto plan = std::make_unique<itp::planner::Plan>();
    for (const auto& [now, sc] : shot.scenes) planner->plan(itp::planner::PlanRequest{sc.get(), now}, *plan);
    const auto& [now, sc] = shot.scenes.back();
    const std::string head = fmt::format("cycle {} (t = {:.1f} s; {}), re-planned in-process: {}{}", shot.cycle, now,
                                         shot.why, itp::to_string(plan->status),
                                         plan->status == itp::PlanStatus::kFallback
                                             ? std::string(" ") + itp::planner::to_string(plan->fallback)
                                             : std::string());
    parts.push_back(plot_sl(*planner, *sc, "SL — " + head));
    parts.push_back(plot_xy(*planner, *sc, *plan, now, "XY — " + head));
    parts.push_back(plot_st(*planner, *plan, "ST — " + head));
  }
  return stack_svgs(parts);
}

// ---------------------------------------------------------------------------
// Summary table

namespace {

std::string num(const json& j, const char* spec = "{:.2f}") {
  if (j.is_null()) return "-";
  if (j.is_number_integer()) return fmt::format("{}", j.get<long long>());
  return fmt::format(fmt::runtime(spec), j.get<double>());
}

}  // namespace

std::string summary_table(const json& rep) {
  std::vector<std::pair<std::string, std::string>> rows;
  auto row = [&](std::string k, std::string v) { rows.emplace_back(std::move(k), std::move(v)); };
  row("target", rep.value("target", std::string("?")));
  row("scenes", num(rep["scenes"]));
  row("cycles", num(rep["cycles"]));
  row("collisions (scenes)", fmt::format("{} ({} steps)", num(rep["collisions"]), num(rep["collision_steps"])));
  if (rep.contains("collisions_ran_into")) {
    row("  the ego ran into / was hit", fmt::format("{} / {}", num(rep["collisions_ran_into"]), num(rep["collisions_hit"])));
  }
  row("road departures (scenes)", fmt::format("{} ({} steps)", num(rep["road_departures"]), num(rep["road_departure_steps"])));
  std::string reasons;
  for (const auto& [k, v] : rep["fallback_reasons"].items()) {
    reasons += fmt::format("{}{} {}", reasons.empty() ? "" : ", ", k, v.get<int>());
  }
  row("fallbacks", fmt::format("{}{}", num(rep["fallbacks"]), reasons.empty() ? "" : " (" + reasons + ")"));
  std::map<std::string, int> invalid;
  for (const auto& sc : rep["per_scene"]) {
    if (sc.contains("invalid_input_reasons")) {
      for (const auto& [k, v] : sc["invalid_input_reasons"].items()) invalid[k] += v.get<int>();
    }
  }
  std::string inv;
  for (const auto& [k, v] : invalid) inv += fmt::format("{}{} {}", inv.empty() ? "" : ", ", k, v);
  row("invalid inputs", fmt::format("{}{}", num(rep["invalid_inputs"]), inv.empty() ? "" : " (" + inv + ")"));
  row("link errors", num(rep["link_errors"]));
  if (rep.contains("link")) {
    const json& l = rep["link"];
    row("cycles without a fresh plan", fmt::format("{} ({:.2f} %), corrupt scenes accepted {}", num(rep["link_errors"]),
                                                   100.0 * rep.value("share_without_fresh_plan", 0.0),
                                                   num(rep["corrupt_scenes_accepted"])));
    row("link: queries / statuses / resent", fmt::format("{} / {} / {}", num(l["queries"]), num(l["statuses"]),
                                                         num(l["segments_resent"])));
    if (l.contains("faults_to_firmware")) {
      row("link: byte faults to fw / to host", fmt::format("{} / {}", num(l["faults_to_firmware"]),
                                                           num(l["faults_to_host"])));
    }
  }
  row("crashes", num(rep["crashes"]));
  if (rep.contains("obstacles_left_out")) {
    const json& lo = rep["obstacles_left_out"];
    row("obstacles left out (capacity)", fmt::format("{} cycles, {} in all, at most {} in a cycle", num(lo["cycles"]),
                                                     num(lo["total"]), num(lo["max_per_cycle"])));
  }
  row("min clearance [m]", num(rep["min_clearance_m"], "{:.3f}"));
  row("max |a_lon| [m/s²]", num(rep["max_abs_lon_acc"]));
  row("max |a_lat| [m/s²]", num(rep["max_abs_lat_acc"]));
  row("max |jerk| [m/s³]", num(rep["max_abs_jerk"], "{:.1f}"));
  row("max plan deviation [m]", num(rep["max_plan_deviation_m"], "{:.3f}"));
  row("path deviation [m] scene median / max",
      fmt::format("{} / {}", num(rep["median_scene_path_deviation_m"], "{:.3f}"), num(rep["max_path_deviation_m"], "{:.3f}")));
  row("iterations mean / max", fmt::format("{} / {}", num(rep["iterations"]["mean"]), num(rep["iterations"]["max"])));
  const json& ct = rep["cycle_time_us"];
  if (!ct["median"].is_null()) {
    row("cycle time [µs] median / p99 / max",
        fmt::format("{} / {} / {}", num(ct["median"], "{:.0f}"), num(ct["p99"], "{:.0f}"), num(ct["max"], "{:.0f}")));
  }
  const json& in = rep["instructions_per_cycle"];
  if (!in["median"].is_null()) {
    row("instructions / cycle median / max", fmt::format("{} / {}", num(in["median"], "{:.3g}"), num(in["max"], "{:.3g}")));
  }
  const double progress = rep.value("progress_m_total", 0.0);
  const int scenes = rep.value("scenes", 0);
  row("progress [m] total / mean per scene",
      fmt::format("{:.0f} / {:.1f}", progress, scenes > 0 ? progress / scenes : 0.0));

  std::size_t w = 0;
  for (const auto& [k, v] : rows) w = std::max(w, k.size());
  std::string out = fmt::format("{:-<{}}\n", "", w + 40);
  for (const auto& [k, v] : rows) out += fmt::format("{:<{}}  {}\n", k, w, v);
  out += fmt::format("{:-<{}}\n", "", w + 40);
  return out;
}

// ---------------------------------------------------------------------------
// hil_sim run

namespace {

class Progress {
 public:
  explicit Progress(int total) : total_(total), tty_(isatty(fileno(stderr)) != 0) {}
  void update(int done, const std::string& name, int collisions, int fallbacks) {
    if (tty_) {
      constexpr int kWidth = 30;
      const int filled = total_ > 0 ? done * kWidth / total_ : kWidth;
      fmt::print(stderr, "\r[{:#<{}}{:.<{}}] {}/{} {} collisions {} fallbacks {}\x1b[K", "", filled, "", kWidth - filled,
                 done, total_, name, collisions, fallbacks);
      if (done == total_) fmt::print(stderr, "\n");
      std::fflush(stderr);
    } else {
      const int decile = total_ > 0 ? done * 10 / total_ : 10;
      if (decile > last_decile_) {
        last_decile_ = decile;
        fmt::print(stderr, "{:3}% {}/{} {} collisions {} fallbacks {}\n", decile * 10, done, total_, name, collisions,
                   fallbacks);
      }
    }
  }

 private:
  int total_;
  bool tty_;
  int last_decile_ = 0;
};

std::string fmt_opt(const std::optional<double>& x, const char* spec) {
  return x ? fmt::format(fmt::runtime(spec), *x) : std::string("-");
}

}  // namespace

namespace {

const char* status_name(PlanStatus s) {
  switch (s) {
    case PlanStatus::kOk: return "ok";
    case PlanStatus::kFallback: return "fallback";
    case PlanStatus::kInvalidInput: return "invalid_input";
    case PlanStatus::kNone: break;
  }
  return "link_error";
}

// One JSON object per cycle: what the planner said and where the ego was.
void write_trace(std::ofstream& out, const std::string& scene, const SceneRunResult& r) {
  for (std::size_t k = 0; k < r.cycles.size(); ++k) {
    const CycleRecord& c = r.cycles[k];
    json j{{"scene", scene}, {"t", c.t}, {"status", status_name(c.status)}, {"reason", c.reason},
           {"iterations", c.iterations}, {"v", c.v}, {"v_plan", c.v_plan}, {"a_lon", c.a_lon},
           {"a_lat", c.a_lat}, {"collision", c.collision}};
    if (c.path_deviation >= 0) {
      j["path_deviation"] = c.path_deviation;
      j["path_deviation_t"] = c.path_deviation_t;
    }
    j["decisions"] = c.decisions;
    if (!c.collision_with.empty()) j["collision_with"] = c.collision_with;
    if (c.left_out > 0) j["obstacles_left_out"] = c.left_out;
    if (c.reference_deviation_m > 0) j["reference_deviation_m"] = c.reference_deviation_m;
    if (c.boundary_narrowing_m > 0) j["boundary_narrowing_m"] = c.boundary_narrowing_m;
    j["clearance"] = c.clearance ? json(*c.clearance) : json(nullptr);
    if (k < r.trace.size()) {
      j["x"] = r.trace[k].pose.x;
      j["y"] = r.trace[k].pose.y;
      j["heading"] = r.trace[k].pose.heading;
    }
    if (c.cycle_time_us >= 0) j["cycle_time_us"] = c.cycle_time_us;
    if (c.instructions >= 0) j["instructions"] = c.instructions;
    if (c.work) {
      const itp::planner::StageTiming& w = *c.work;
      j["work"] = json{{"tick_hz", w.tick_hz},
                       {"prepare", w.prepare},
                       {"decision", w.decision},
                       {"coarse", w.coarse},
                       {"path", w.path},
                       {"speed", w.speed},
                       {"check", w.check},
                       {"total", w.total},
                       {"decision_runs", w.decision_runs},
                       {"tree_nodes", w.tree_nodes},
                       {"coarse_qps", w.coarse_qps},
                       {"coarse_iterations", w.coarse_iterations},
                       {"path_solves", w.path_solves},
                       {"path_iterations", w.path_iterations},
                       {"speed_solves", w.speed_solves},
                       {"speed_iterations", w.speed_iterations}};
    }
    out << j.dump() << '\n';
  }
}

}  // namespace

int run_command(const RunCommand& cmd) {
  // Scenes.
  std::vector<World> worlds;
  if (!cmd.scene_files.empty()) {
    for (const auto& path : cmd.scene_files) {
      LoadedScene loaded = load_scene(path, cmd.commonroad);
      if (!loaded) {
        fmt::print(stderr, "hil_sim run: {}\n", loaded.error);
        return 2;
      }
      for (const std::string& note : loaded.notes) fmt::print(stderr, "hil_sim run: {}: {}\n", path, note);
      worlds.push_back(std::move(*loaded.world));
    }
  } else if (cmd.suite == "default") {
    worlds = default_suite(cmd.count, cmd.seed);
  } else if (cmd.suite == "stress") {
    // The envelope's corner: 10 static + 5 dynamic obstacles in every scene
    // (a slot whose candidates keep breaking the generator's rules stays empty).
    GeneratorConfig config;
    config.min_static = config.max_static = 10;
    config.min_dynamic = config.max_dynamic = 5;
    worlds = default_suite(cmd.count, cmd.seed, config);
  } else {
    fmt::print(stderr, "hil_sim run: unknown suite '{}' (known: default, stress)\n", cmd.suite);
    return 2;
  }

  // Endpoint.
  std::unique_ptr<PlannerEndpoint> endpoint;
  std::string why;
  LinkOptions link;
  link.key_file = cmd.key_file;
  link.deadline = std::chrono::milliseconds(cmd.link_deadline_ms);
  if (!cmd.link_faults.empty()) {
    const auto faults = parse_link_faults(cmd.link_faults, why);
    if (!faults) {
      fmt::print(stderr, "hil_sim run: --link-faults: {}\n", why);
      return 2;
    }
    link.faults = *faults;
  }
  if (cmd.target == "inproc") {
    if (link.faults.any()) {
      fmt::print(stderr, "hil_sim run: --link-faults needs a link (--target host or qemu)\n");
      return 2;
    }
    endpoint = std::make_unique<InprocEndpoint>();
  } else if (cmd.target == "host" || cmd.target == "qemu") {
    endpoint = make_link_endpoint(cmd.target, cmd.firmware, &why, link);
  }
  if (!endpoint) {
    fmt::print(stderr, "hil_sim run: cannot use target '{}'{}\n", cmd.target, why.empty() ? "" : ": " + why);
    return 2;
  }

  RunOptions opt;
  opt.prediction = cmd.prediction == "truth" ? Prediction::kGroundTruth : Prediction::kConstantVelocity;
  opt.duration = cmd.duration;
  opt.keep_snapshot = !cmd.plots.empty();
  if (!cmd.plots.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(cmd.plots, ec);
    if (ec) {
      fmt::print(stderr, "hil_sim run: cannot create '{}': {}\n", cmd.plots, ec.message());
      return 2;
    }
  }

  fmt::print("hil_sim run: {} scenes, target {}, prediction {}{}\n", worlds.size(), endpoint->name(),
             opt.prediction == Prediction::kGroundTruth ? "ground truth" : "constant velocity",
             link.faults.any() ? ", link faults " + to_string(link.faults) : std::string());
  std::fflush(stdout);
  std::ofstream trace;
  if (!cmd.trace.empty()) {
    trace.open(cmd.trace);
    if (!trace) {
      fmt::print(stderr, "hil_sim run: cannot write '{}'\n", cmd.trace);
      return 2;
    }
  }
  SuiteAggregator suite;
  std::vector<svg::IndexRow> rows;
  Progress progress(static_cast<int>(worlds.size()));
  int collisions = 0, fallbacks = 0;
  for (std::size_t i = 0; i < worlds.size(); ++i) {
    const World& w = worlds[i];
    SceneRunResult r = run_scene(w, *endpoint, opt);
    const SceneSummary& s = r.summary;
    collisions += s.collided() ? 1 : 0;
    fallbacks += s.fallbacks;
    if (!r.error.empty()) fmt::print(stderr, "\nhil_sim run: {}: {}\n", w.name, r.error);
    if (trace.is_open()) write_trace(trace, w.name, r);
    if (!cmd.plots.empty()) {
      const std::string file = w.name + ".svg";
      if (!svg::write_text_file((std::filesystem::path(cmd.plots) / file).string(), scene_run_svg(w, r))) {
        fmt::print(stderr, "hil_sim run: cannot write {}/{}\n", cmd.plots, file);
        return 2;
      }
      std::vector<double> it(s.iterations.begin(), s.iterations.end());
      const Stats is = compute_stats(it);
      svg::IndexRow row;
      row.name = w.name;
      row.ok = !s.collided() && !s.departed() && !s.crashed && s.fallbacks == 0 && s.invalid_inputs == 0 &&
               s.link_errors == 0;
      row.links = {{"svg", file}};
      std::string tags;
      for (const auto& t : w.tags) tags += (tags.empty() ? "" : " ") + t;
      row.metrics = {{"collision", s.collided() ? "yes" : ""},
                     {"departure", s.departed() ? fmt::format("{:.2f} m", s.max_road_excess_m) : ""},
                     {"fallbacks", s.fallbacks ? fmt::format("{}", s.fallbacks) : ""},
                     {"invalid", s.invalid_inputs ? fmt::format("{}", s.invalid_inputs) : ""},
                     {"link err.", s.link_errors ? fmt::format("{}", s.link_errors) : ""},
                     {"min clear. [m]", fmt_opt(s.min_clearance_m, "{:.2f}")},
                     {"progress [m]", fmt::format("{:.1f}", s.progress_m)},
                     {"max |a_lon|", fmt::format("{:.2f}", s.max_abs_lon_acc)},
                     {"max |a_lat|", fmt::format("{:.2f}", s.max_abs_lat_acc)},
                     {"max |jerk|", fmt::format("{:.1f}", s.max_abs_jerk)},
                     {"iter. mean/max", is.mean ? fmt::format("{:.2f} / {:.0f}", *is.mean, *is.max) : "-"},
                     {"tags", tags}};
      rows.push_back(std::move(row));
    }
    suite.add(s);
    progress.update(static_cast<int>(i + 1), w.name, collisions, fallbacks);
  }

  json rep = suite.report(endpoint->name());
  const json link_stats = endpoint->link_statistics();
  if (!link_stats.is_null()) rep["link"] = link_stats;
  fmt::print("{}", summary_table(rep));
  if (!cmd.report.empty()) {
    const std::string err = write_report(rep, cmd.report);
    if (!err.empty()) {
      fmt::print(stderr, "hil_sim run: {}\n", err);
      return 2;
    }
    fmt::print("report: {}\n", cmd.report);
  }
  if (!cmd.plots.empty()) {
    std::vector<std::string> lines;
    std::istringstream table(summary_table(rep));
    for (std::string line; std::getline(table, line);) {
      if (!line.empty() && line.front() != '-') lines.push_back(line);
    }
    const std::string index = (std::filesystem::path(cmd.plots) / "index.html").string();
    if (!svg::write_text_file(index, svg::index_html(fmt::format("hil_sim run — {} scenes, target {}",
                                                                 worlds.size(), endpoint->name()),
                                                     lines, rows))) {
      fmt::print(stderr, "hil_sim run: cannot write {}\n", index);
      return 2;
    }
    fmt::print("plots: {}\n", index);
  }
  if (rep.value("crashes", 0) > 0) return 3;
  // A link that failed is a failed run, not a result (issue 13, defect 8: a
  // run where every cycle was a link error exited 0).
  const int link_errors = rep.value("link_errors", 0);
  const int no_plan = rep.value("scenes_without_any_plan", 0);
  if ((link_errors > 0 && !link.faults.any()) || no_plan > 0) {
    fmt::print(stderr, "hil_sim run: the link failed: {} cycles without a plan, {} scenes without any{}\n", link_errors,
               no_plan, link.faults.any() ? "" : " (no faults were injected)");
    return 4;
  }
  return 0;
}

}  // namespace hil::sim
