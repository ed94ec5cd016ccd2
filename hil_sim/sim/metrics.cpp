#include "sim/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace hil::sim {

using nlohmann::json;

double road_margin(std::span<const Point2> ref, const Road& road, const OrientedBox& box) {
  double m = std::numeric_limits<double>::infinity();
  for (const Point2& c : box.corners()) {
    const PolylineProjection p = project_to_polyline(ref, c.x, c.y);
    m = std::min({m, road.left_boundary.at(p.s) - p.l, p.l - road.right_boundary.at(p.s)});
  }
  return m;
}

SceneMetrics::SceneMetrics(std::string name, std::vector<std::string> tags) {
  s_.name = std::move(name);
  s_.tags = std::move(tags);
}

SceneSummary::CollisionKind who_ran_into(const OrientedBox& ego, Point2 v_ego, const OrientedBox& obstacle,
                                          Point2 v_obstacle) {
  double nx = obstacle.cx - ego.cx;
  double ny = obstacle.cy - ego.cy;
  const double norm = std::hypot(nx, ny);
  if (norm > 0.0) {
    nx /= norm;
    ny /= norm;
  }
  const double ego_share = v_ego.x * nx + v_ego.y * ny;
  const double obstacle_share = -(v_obstacle.x * nx + v_obstacle.y * ny);
  return ego_share >= obstacle_share ? SceneSummary::CollisionKind::kRanInto : SceneSummary::CollisionKind::kHit;
}

void SceneMetrics::add_step(const StepSample& x) {
  ++s_.steps;
  bool hit = false;
  for (std::size_t i = 0; i < x.obstacles.size(); ++i) {
    const OrientedBox& o = x.obstacles[i];
    const double d = box_distance(x.ego, o);
    if (d <= 0.0 && s_.collision_kind == SceneSummary::CollisionKind::kNone) {
      const Point2 v_obs = i < x.obstacle_velocities.size() ? x.obstacle_velocities[i] : Point2{};
      s_.collision_kind = who_ran_into(x.ego, x.ego_velocity, o, v_obs);
    }
    hit = hit || d <= 0.0;
    s_.min_clearance_m = s_.min_clearance_m ? std::min(*s_.min_clearance_m, d) : d;
  }
  if (hit) ++s_.collision_steps;
  if (x.road_margin < 0.0) {
    ++s_.road_departure_steps;
    s_.max_road_excess_m = std::max(s_.max_road_excess_m, -x.road_margin);
  }
  if (!first_s_) first_s_ = x.progress_s;
  s_.progress_m = x.progress_s - *first_s_;
  s_.max_abs_lon_acc = std::max(s_.max_abs_lon_acc, std::abs(x.a_lon));
  s_.max_abs_lat_acc = std::max(s_.max_abs_lat_acc, std::abs(x.a_lat));
  if (last_a_lon_ && x.t > last_t_) {
    s_.max_abs_jerk = std::max(s_.max_abs_jerk, std::abs(x.a_lon - *last_a_lon_) / (x.t - last_t_));
  }
  last_a_lon_ = x.a_lon;
  last_t_ = x.t;
  s_.max_abs_lateral_offset = std::max(s_.max_abs_lateral_offset, std::abs(x.lateral_offset));
  s_.max_abs_heading_error = std::max(s_.max_abs_heading_error, std::abs(x.heading_error));

  if (x.status) {
    ++s_.cycles;
    if (x.status == itp::PlanStatus::kFallback) {
      ++s_.fallbacks;
      ++s_.fallback_reasons[x.reason.empty() ? "unspecified" : x.reason];
    } else if (x.status == itp::PlanStatus::kInvalidInput) {
      ++s_.invalid_inputs;
      ++s_.invalid_input_reasons[x.reason.empty() ? "unspecified" : x.reason];
    }
    if (x.iterations) s_.iterations.push_back(*x.iterations);
    if (x.cycle_time_us) s_.cycle_time_us.push_back(*x.cycle_time_us);
    if (x.instructions) s_.instructions.push_back(*x.instructions);
  }
}

double SceneMetrics::add_plan(double t_start, std::span<const TrajectoryPoint> plan) {
  if (plan.empty()) return -1.0;
  double cycle_path_dev = -1.0;
  if (!prev_plan_.empty()) {
    // Common absolute times: the new plan's samples inside the previous plan's span.
    const double prev_end = prev_start_ + prev_plan_.back().t;
    double dev = 0.0;
    bool any = false;
    for (const auto& q : plan) {
      const double ta = t_start + q.t;
      if (ta < prev_start_ + prev_plan_.front().t || ta > prev_end) continue;
      const TrajectoryPoint p = sample_plan(prev_plan_, ta - prev_start_);
      // Lateral component w.r.t. the new plan's heading.
      const double d = -(p.x - q.x) * std::sin(q.heading) + (p.y - q.y) * std::cos(q.heading);
      dev = std::max(dev, std::abs(d));
      any = true;
    }
    if (any) s_.max_plan_deviation_m = std::max(s_.max_plan_deviation_m.value_or(0.0), dev);
    // Path flip-flop, independent of speed changes: how far the new plan's
    // points lie from the previous plan's path, where the two paths overlap.
    std::vector<Point2> prev_path;
    for (const auto& p : prev_plan_) {
      if (prev_path.empty() || std::hypot(p.x - prev_path.back().x, p.y - prev_path.back().y) > 0.05) {
        prev_path.push_back({p.x, p.y});
      }
    }
    if (prev_path.size() >= 2) {
      double length = 0.0;
      for (std::size_t i = 1; i < prev_path.size(); ++i) {
        length += std::hypot(prev_path[i].x - prev_path[i - 1].x, prev_path[i].y - prev_path[i - 1].y);
      }
      double path_dev = 0.0;
      bool any_path = false;
      for (const auto& q : plan) {
        const PolylineProjection pr = project_to_polyline(prev_path, q.x, q.y);
        if (pr.s < 0.0 || pr.s > length) continue;  // beyond the previous path's ends
        if (std::abs(pr.l) > path_dev) {
          path_dev = std::abs(pr.l);
          last_dev_t_ = q.t;
        }
        any_path = true;
      }
      if (any_path) {
        s_.max_path_deviation_m = std::max(s_.max_path_deviation_m.value_or(0.0), path_dev);
        cycle_path_dev = path_dev;
      }
    }
  }
  prev_plan_.assign(plan.begin(), plan.end());
  prev_start_ = t_start;
  return cycle_path_dev;
}

void SceneMetrics::add_link_error(int count) { s_.link_errors += count; }

void SceneMetrics::add_left_out(int count) {
  if (count <= 0) return;
  ++s_.left_out_cycles;
  s_.left_out_total += count;
  s_.left_out_max = std::max(s_.left_out_max, count);
}

void SceneMetrics::set_crashed(std::string reason) {
  s_.crashed = true;
  s_.crash_reason = std::move(reason);
}

Stats compute_stats(std::vector<double> v) {
  Stats st;
  if (v.empty()) return st;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  st.median = (n % 2 == 1) ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  const auto rank = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(n)));
  st.p99 = v[std::max<std::size_t>(rank, 1) - 1];
  st.max = v.back();
  double sum = 0.0;
  for (double x : v) sum += x;
  st.mean = sum / static_cast<double>(n);
  return st;
}

namespace {
json opt(const std::optional<double>& x) { return x ? json(*x) : json(nullptr); }
json left_out_json(int cycles, int total, int max_per_cycle) {
  return json{{"cycles", cycles}, {"total", total}, {"max_per_cycle", max_per_cycle}};
}
}  // namespace

const char* collision_kind_name(SceneSummary::CollisionKind k) {
  switch (k) {
    case SceneSummary::CollisionKind::kRanInto: return "ran_into";
    case SceneSummary::CollisionKind::kHit: return "hit";
    case SceneSummary::CollisionKind::kNone: break;
  }
  return "none";
}

json scene_summary_json(const SceneSummary& s) {
  std::vector<double> it(s.iterations.begin(), s.iterations.end());
  const Stats is = compute_stats(it);
  const Stats ct = compute_stats(s.cycle_time_us);
  const Stats in = compute_stats(s.instructions);
  json j = {{"name", s.name},
            {"steps", s.steps},
            {"cycles", s.cycles},
            {"collisions", s.collision_steps > 0 ? 1 : 0},
            {"collision_steps", s.collision_steps},
            {"collision_kind", collision_kind_name(s.collision_kind)},
            {"road_departures", s.road_departure_steps > 0 ? 1 : 0},
            {"road_departure_steps", s.road_departure_steps},
            {"max_road_excess_m", s.max_road_excess_m},
            {"fallbacks", s.fallbacks},
            {"fallback_reasons", s.fallback_reasons},
            {"invalid_inputs", s.invalid_inputs},
            {"link_errors", s.link_errors},
            {"corrupt_scenes_accepted", s.corrupt_scenes_accepted},
            {"crashed", s.crashed},
            {"min_clearance_m", opt(s.min_clearance_m)},
            {"progress_m", s.progress_m},
            {"max_abs_lon_acc", s.max_abs_lon_acc},
            {"max_abs_lat_acc", s.max_abs_lat_acc},
            {"max_abs_jerk", s.max_abs_jerk},
            {"max_abs_lateral_offset_m", s.max_abs_lateral_offset},
            {"max_abs_heading_error_rad", s.max_abs_heading_error},
            {"max_plan_deviation_m", opt(s.max_plan_deviation_m)},
            {"max_path_deviation_m", opt(s.max_path_deviation_m)},
            {"iterations",
             {{"mean", opt(is.mean)},
              {"max", is.max ? json(static_cast<int>(*is.max)) : json(nullptr)}}},
            {"cycle_time_us", {{"median", opt(ct.median)}, {"p99", opt(ct.p99)}, {"max", opt(ct.max)}}},
            {"instructions_per_cycle", {{"median", opt(in.median)}, {"max", opt(in.max)}}}};
  if (s.crashed) j["crash_reason"] = s.crash_reason;
  if (s.left_out_cycles > 0) j["obstacles_left_out"] = left_out_json(s.left_out_cycles, s.left_out_total, s.left_out_max);
  if (!s.invalid_input_reasons.empty()) j["invalid_input_reasons"] = s.invalid_input_reasons;
  if (!s.tags.empty()) j["tags"] = s.tags;
  return j;
}

void SuiteAggregator::add(SceneSummary scene) { scenes_.push_back(std::move(scene)); }

json SuiteAggregator::report(const std::string& target) const {
  int cycles = 0, collisions = 0, collision_steps = 0, departures = 0, departure_steps = 0;
  int ran_into = 0, hit = 0;
  int fallbacks = 0, invalid = 0, link_errors = 0, crashes = 0, corrupt = 0, no_plan_scenes = 0;
  int left_out_cycles = 0, left_out_total = 0, left_out_max = 0;
  std::optional<double> min_clear;
  double max_lat = 0.0, max_lon = 0.0, max_jerk = 0.0, progress = 0.0;
  std::optional<double> max_dev;
  std::optional<double> max_path_dev;
  std::vector<double> path_devs;
  std::map<std::string, int> reasons;
  std::vector<double> iters, ctime, instr;
  json per_scene = json::array();
  for (const auto& s : scenes_) {
    cycles += s.cycles;
    collisions += s.collided() ? 1 : 0;
    collision_steps += s.collision_steps;
    ran_into += s.collision_kind == SceneSummary::CollisionKind::kRanInto ? 1 : 0;
    hit += s.collision_kind == SceneSummary::CollisionKind::kHit ? 1 : 0;
    departures += s.departed() ? 1 : 0;
    departure_steps += s.road_departure_steps;
    fallbacks += s.fallbacks;
    invalid += s.invalid_inputs;
    link_errors += s.link_errors;
    corrupt += s.corrupt_scenes_accepted;
    no_plan_scenes += s.link_errors > 0 && s.cycles == 0 ? 1 : 0;
    crashes += s.crashed ? 1 : 0;
    left_out_cycles += s.left_out_cycles;
    left_out_total += s.left_out_total;
    left_out_max = std::max(left_out_max, s.left_out_max);
    if (s.min_clearance_m) min_clear = min_clear ? std::min(*min_clear, *s.min_clearance_m) : *s.min_clearance_m;
    if (s.max_plan_deviation_m) max_dev = std::max(max_dev.value_or(0.0), *s.max_plan_deviation_m);
    if (s.max_path_deviation_m) {
      max_path_dev = std::max(max_path_dev.value_or(0.0), *s.max_path_deviation_m);
      path_devs.push_back(*s.max_path_deviation_m);
    }
    max_lat = std::max(max_lat, s.max_abs_lat_acc);
    max_lon = std::max(max_lon, s.max_abs_lon_acc);
    max_jerk = std::max(max_jerk, s.max_abs_jerk);
    progress += s.progress_m;
    for (const auto& [k, n] : s.fallback_reasons) reasons[k] += n;
    iters.insert(iters.end(), s.iterations.begin(), s.iterations.end());
    ctime.insert(ctime.end(), s.cycle_time_us.begin(), s.cycle_time_us.end());
    instr.insert(instr.end(), s.instructions.begin(), s.instructions.end());
    per_scene.push_back(scene_summary_json(s));
  }
  const Stats is = compute_stats(iters);
  const Stats ct = compute_stats(ctime);
  const Stats in = compute_stats(instr);
  const bool any = !scenes_.empty();
  json j = {{"format", "report/1"},
            {"target", target},
            {"scenes", static_cast<int>(scenes_.size())},
            {"cycles", cycles},
            {"collisions", collisions},
            {"road_departures", departures},
            {"fallbacks", fallbacks},
            {"invalid_inputs", invalid},
            {"link_errors", link_errors},
            {"crashes", crashes},
            {"min_clearance_m", opt(min_clear)},
            {"max_abs_lat_acc", any ? json(max_lat) : json(nullptr)},
            {"max_abs_lon_acc", any ? json(max_lon) : json(nullptr)},
            {"iterations",
             {{"mean", opt(is.mean)},
              {"max", is.max ? json(static_cast<int>(*is.max)) : json(nullptr)}}},
            {"cycle_time_us", {{"median", opt(ct.median)}, {"p99", opt(ct.p99)}, {"max", opt(ct.max)}}},
            {"instructions_per_cycle", {{"median", opt(in.median)}, {"max", opt(in.max)}}},
            // Extensions (optional keys, docs/simulation.md).
            {"collision_steps", collision_steps},
            {"collisions_ran_into", ran_into},
            {"collisions_hit", hit},
            {"road_departure_steps", departure_steps},
            {"fallback_reasons", reasons},
            {"max_abs_jerk", any ? json(max_jerk) : json(nullptr)},
            {"max_plan_deviation_m", opt(max_dev)},
            {"max_path_deviation_m", opt(max_path_dev)},
            {"median_scene_path_deviation_m", opt(compute_stats(path_devs).median)},
            {"progress_m_total", progress},
            // The link (docs/simulation.md, "Link faults"): planning cycles that
            // got no fresh plan, their share, and scenes that never got one.
            {"cycles_without_fresh_plan", link_errors},
            {"share_without_fresh_plan",
             cycles + link_errors > 0 ? static_cast<double>(link_errors) / (cycles + link_errors) : 0.0},
            {"scenes_without_any_plan", no_plan_scenes},
            {"corrupt_scenes_accepted", corrupt},
            {"per_scene", std::move(per_scene)}};
  if (left_out_cycles > 0) j["obstacles_left_out"] = left_out_json(left_out_cycles, left_out_total, left_out_max);
  return j;
}

std::string write_report(const json& report, const std::string& path) {
  std::ofstream out(path);
  if (!out) return fmt::format("cannot write '{}'", path);
  out << report.dump(2) << "\n";
  return out ? std::string{} : fmt::format("error writing '{}'", path);
}

}  // namespace hil::sim
