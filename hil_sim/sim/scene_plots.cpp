#include "sim/scene_plots.hpp"

#include <algorithm>
#include <memory>
#include <type_traits>
#include <variant>
#include <vector>

#include <fmt/core.h>
#include <fmt/format.h>

#include "itp/planner/planner.hpp"
#include "sim/metrics.hpp"
#include "sim/plan_plots.hpp"

namespace hil::sim {
namespace {

std::string fmt_opt(const std::optional<double>& x, const char* spec) {
  return x ? fmt::format(fmt::runtime(spec), *x) : std::string("-");
}

// The configuration of a BasicScene<Cfg>.
template <class Scene>
struct SceneConfig;
template <class Cfg>
struct SceneConfig<itp::scene::BasicScene<Cfg>> {
  using type = Cfg;
};

// Re-plans the snapshot's cycle in-process (after its predecessor, for
// stitching) with the planner of the scenes' configuration, and draws its SL,
// XY and ST views.
template <class Cfg>
void replot_snapshot(const CycleSnapshot& shot, std::vector<std::string>& parts) {
  auto planner = std::make_unique<itp::planner::BasicPlanner<Cfg>>();
  auto plan = std::make_unique<itp::planner::BasicPlan<Cfg>>();
  for (const auto& [now, any] : shot.scenes) {
    planner->plan(itp::planner::BasicPlanRequest<Cfg>{std::get<SceneRef<Cfg>>(any).get(), now}, *plan);
  }
  const double now = shot.scenes.back().first;
  const itp::scene::BasicScene<Cfg>& sc = *std::get<SceneRef<Cfg>>(shot.scenes.back().second);
  const std::string head = fmt::format("cycle {} (t = {:.1f} s; {}), re-planned in-process: {}{}", shot.cycle, now,
                                       shot.why, itp::to_string(plan->status),
                                       plan->status == itp::PlanStatus::kFallback
                                           ? std::string(" ") + itp::planner::to_string(plan->fallback)
                                           : std::string());
  parts.push_back(plot_sl(*planner, sc, "SL — " + head));
  parts.push_back(plot_xy(*planner, sc, *plan, now, "XY — " + head));
  parts.push_back(plot_st(*planner, *plan, "ST — " + head));
}

}  // namespace

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
    if (c.status == itp::PlanStatus::kOk || c.status == itp::PlanStatus::kFallback) speed[1].points.push_back({c.t, c.v_plan});
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
    // plan/1's status codes (itp::PlanStatus: 0, 1, 2), and 3 for no plan at all.
    const double code = c.status ? static_cast<double>(*c.status) : 3.0;
    other[3].points.push_back({c.t, code});
    other[3].points.push_back({c.t + 0.1, code});
  }
  parts.push_back(plot_line_chart("clearance, accelerations, plan status", "t [s]", "", other));

  for (const CycleSnapshot& shot : r.snapshots) {
    if (shot.scenes.empty()) continue;
    // The snapshot's scenes are of the configuration the run planned with:
    // re-plan with that one.
    std::visit(
        [&](const auto& first) {
          using Scene = std::remove_const_t<typename std::decay_t<decltype(first)>::element_type>;
          replot_snapshot<typename SceneConfig<Scene>::type>(shot, parts);
        },
        shot.scenes.front().second);
  }
  return stack_svgs(parts);
}

svg::IndexRow scene_index_row(const World& w, const SceneSummary& s, const std::string& svg_file) {
  std::vector<double> it(s.iterations.begin(), s.iterations.end());
  const Stats is = compute_stats(it);
  svg::IndexRow row;
  row.name = w.name;
  row.ok = !s.collided() && !s.departed() && !s.crashed && s.fallbacks == 0 && s.invalid_inputs == 0 &&
           s.link_errors == 0;
  row.links = {{"svg", svg_file}};
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
  return row;
}

}  // namespace hil::sim
