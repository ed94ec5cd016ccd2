#include "sim/plan_plots.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <regex>
#include <type_traits>

#include "itp/decision/corridor.hpp"
#include "itp/scene/obstacle_motion.hpp"
#include "sim/svg.hpp"

namespace hil::sim {
namespace {

using svg::Canvas;
using svg::Style;

constexpr const char* kZone = "#dfe7ef";
constexpr const char* kCorridor = "#9ecae1";
constexpr const char* kPath = "#0072B2";
constexpr const char* kCoarse = "#E69F00";

std::vector<Point2> rect(double s0, double s1, double l0, double l1) {
  return {{s0, l0}, {s1, l0}, {s1, l1}, {s0, l1}};
}

}  // namespace

template <class Cfg>
std::string plot_sl(const itp::planner::BasicPlanner<Cfg>& planner, const itp::scene::BasicScene<Cfg>& scene,
                    const std::string& title) {
  const double s0 = planner.path_start();
  const double s1 = s0 + planner.path_length();
  double l_lo = -2;
  double l_hi = 2;
  for (double s = s0; s <= s1; s += 1.0) {
    l_lo = std::min(l_lo, scene.road.right.at(s) - 1.0);
    l_hi = std::max(l_hi, scene.road.left.at(s) + 1.0);
  }
  Canvas c(1400, 420);
  c.set_view(s0 - 5, s1 + 5, l_lo, l_hi, false);
  c.title(title);
  c.axes("s [m] along the reference line", "l [m]");
  c.begin_clip();
  // Road edges.
  std::vector<Point2> left;
  std::vector<Point2> right;
  for (double s = s0 - 5; s <= s1 + 5; s += 1.0) {
    left.push_back({s, scene.road.left.at(s)});
    right.push_back({s, scene.road.right.at(s)});
  }
  c.polyline(left, Style(svg::colour::kRoadEdge, "none", 2));
  c.polyline(right, Style(svg::colour::kRoadEdge, "none", 2));
  // Zones, then the chosen corridor on top.
  const auto& stage = planner.decision_stage();
  const auto zone_rect = [&](const itp::decision::Zone& z) {
    const itp::decision::Slice& slice = stage.space().slice_of(z);
    return rect(slice.s_begin, slice.s_end, z.l_min, z.l_max);
  };
  for (const auto& z : stage.space().zones) {
    c.polygon(zone_rect(z), Style("#9aa5b1", kZone, 0.8, 0.8));
  }
  const int chosen = planner.chosen_decision();
  if (chosen >= 0) {
    const auto& d = stage.decisions().kept[static_cast<std::size_t>(chosen)];
    for (std::int16_t zi : d.zones) {
      const auto& z = stage.space().zones[static_cast<std::size_t>(zi)];
      c.polygon(zone_rect(z), Style(kPath, kCorridor, 1.2, 0.7));
    }
  }
  // Obstacles (as the planner sees them: inflated SL boxes).
  for (const auto& b : planner.boxes()) {
    c.polygon(rect(b.s_min, b.s_max, b.l_min, b.l_max),
              Style(b.dynamic ? svg::colour::kDynamic : svg::colour::kStatic,
                    b.dynamic ? svg::colour::kDynamic : svg::colour::kStatic, 1, 0.55));
    c.text(0.5 * (b.s_min + b.s_max), b.l_max + 0.3, fmt::format("#{}", b.obstacle_id), 11, "middle");
  }
  // Coarse samples of every kept decision (the chosen one bold), and the path.
  // The stage keeps only scores: each usable decision's samples come from its
  // coarse QP solved again (evaluate_again).
  using Stage = std::remove_cvref_t<decltype(stage)>;
  auto arena = std::make_unique<typename Stage::QpArena>();  // its own: the planner's stays untouched
  auto evaluator = std::make_unique<typename Stage::CoarseEvaluator>(*arena);
  auto again = std::make_unique<typename Stage::CoarseResult>();
  for (std::size_t i = 0; i < stage.decisions().kept.size(); ++i) {
    if (!itp::qp::is_usable(stage.coarse(i).status)) continue;
    stage.evaluate_again(i, *evaluator, *again);
    const auto& cr = *again;
    if (!itp::qp::is_usable(cr.status)) continue;
    std::vector<Point2> pts;
    for (int k = 0; k < cr.samples; ++k) {
      pts.push_back({cr.s[static_cast<std::size_t>(k)], cr.l[static_cast<std::size_t>(k)]});
    }
    const bool best = static_cast<int>(i) == chosen;
    c.polyline(pts, Style(kCoarse, "none", best ? 1.8 : 0.8, best ? 1.0 : 0.5, best ? "" : "4 3"));
    if (best) {
      for (const auto& p : pts) c.circle(p.x, p.y, 3, Style(kCoarse, kCoarse, 1));
    }
  }
  if (itp::qp::is_usable(planner.path_result().status)) {
    std::vector<Point2> path;
    for (double s = s0; s <= s1; s += 0.5) path.push_back({s, planner.path_result().eval(s, 0)});
    c.polyline(path, Style(kPath, "none", 2.5));
  }
  c.end_clip();
  const std::vector<svg::LegendEntry> legend{
      {"zone", Style("#9aa5b1", kZone, 1), true},
      {"chosen corridor", Style(kPath, kCorridor, 1), true},
      {"obstacle (SL box)", Style(svg::colour::kStatic, svg::colour::kStatic, 1, 0.55), true},
      {"coarse QP samples", Style(kCoarse, "none", 1.8), false},
      {"path QP l(s)", Style(kPath, "none", 2.5), false}};
  c.legend(legend);
  return c.str();
}

template <class Cfg>
std::string plot_xy(const itp::planner::BasicPlanner<Cfg>& planner, const itp::scene::BasicScene<Cfg>& scene,
                    const itp::planner::BasicPlan<Cfg>& plan, double now, const std::string& title) {
  const auto& line = planner.reference_line();
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  std::vector<Point2> left, right, ref;
  const double s0 = std::max(0.0, static_cast<double>(planner.path_start()) - 10);
  const double s1 = std::min(static_cast<double>(line.length()), static_cast<double>(planner.path_start() + planner.path_length()) + 5);
  for (double s = s0; s <= s1; s += 1.0) {
    const auto r = line.evaluate(s);
    const auto at = [&](double l) {
      return Point2{r.position.x - l * std::sin(r.heading), r.position.y + l * std::cos(r.heading)};
    };
    left.push_back(at(scene.road.left.at(s)));
    right.push_back(at(scene.road.right.at(s)));
    ref.push_back(at(0));
    for (const auto& p : {left.back(), right.back()}) {
      x0 = std::min(x0, p.x); x1 = std::max(x1, p.x); y0 = std::min(y0, p.y); y1 = std::max(y1, p.y);
    }
  }
  if (left.empty()) {
    return Canvas(10, 10).str();
  }
  Canvas c(1400, 560);
  c.set_view(x0 - 5, x1 + 5, y0 - 5, y1 + 5, true);
  c.title(title);
  c.axes("x [m]", "y [m]");
  c.begin_clip();
  c.polyline(left, Style(svg::colour::kRoadEdge, "none", 2));
  c.polyline(right, Style(svg::colour::kRoadEdge, "none", 2));
  c.polyline(ref, Style(svg::colour::kReference, "none", 1, 1, "6 4"));
  for (const auto& o : scene.static_obstacles) {
    c.box(OrientedBox{o.x, o.y, o.heading, o.length, o.width}, Style(svg::colour::kStatic, svg::colour::kStatic, 1, 0.8));
  }
  const auto& g = scene.ego.geometry;
  const double rear = 0.5 * (g.length - g.wheelbase);
  for (std::size_t k = 0; k < plan.trajectory.size(); k += 5) {
    const auto& p = plan.trajectory[k];
    const double op = 0.25 + 0.6 * (1.0 - static_cast<double>(k) / static_cast<double>(plan.trajectory.size()));
    const double ahead = 0.5 * g.length - rear;
    c.box(OrientedBox{p.x + ahead * std::cos(p.heading), p.y + ahead * std::sin(p.heading), p.heading, g.length, g.width},
          Style(svg::colour::kEgo, "none", 1.2, op));
    for (const auto& o : scene.dynamic_obstacles) {
      const auto q = itp::scene::sample_pose(o, now + p.t);
      if (q.present) {
        c.box(OrientedBox{q.x, q.y, q.heading, o.length, o.width}, Style(svg::colour::kDynamic, "none", 1.2, op));
      }
    }
  }
  std::vector<Point2> traj;
  for (const auto& p : plan.trajectory) traj.push_back({p.x, p.y});
  c.polyline(traj, Style(svg::colour::kEgo, "none", 2));
  c.end_clip();
  const std::vector<svg::LegendEntry> legend{
      {"ego every 0.5 s", Style(svg::colour::kEgo, "none", 1.2), true},
      {"moving obstacle, same times", Style(svg::colour::kDynamic, "none", 1.2), true},
      {"static obstacle", Style(svg::colour::kStatic, svg::colour::kStatic, 1), true}};
  c.legend(legend);
  return c.str();
}

template <class Cfg>
std::string plot_st(const itp::planner::BasicPlanner<Cfg>& planner, const itp::planner::BasicPlan<Cfg>& plan,
                    const std::string& title) {
  const auto& bounds = planner.speed_bounds();
  double s_max = 10;
  for (const auto& p : plan.trajectory) s_max = std::max(s_max, static_cast<double>(p.s - planner.path_start()));
  for (double v : bounds.s_ref) s_max = std::max(s_max, v);
  Canvas c(1400, 380);
  c.set_view(0, Cfg::kSpeedHorizon, 0, s_max * 1.1, false);
  c.title(title);
  c.axes("t [s]", "s [m] travelled along the path");
  c.begin_clip();
  const double dt = Cfg::kSpeedHorizon / Cfg::kSpeedSamples;
  for (const auto& d : planner.st_graph().decisions()) {
    for (int k = 0; k < Cfg::kStSamples; ++k) {
      const auto u = static_cast<std::size_t>(k);
      if (!d.conflict[u]) continue;
      c.polygon(std::vector<Point2>{{k * dt, d.s_lo[u]}, {k * dt + dt, d.s_lo[u]}, {k * dt + dt, d.s_hi[u]}, {k * dt, d.s_hi[u]}},
                Style("none", svg::colour::kDynamic, 0, 0.35));
    }
  }
  std::vector<Point2> hi, lo, ref, s;
  for (int k = 0; k < Cfg::kStSamples; ++k) {
    const auto u = static_cast<std::size_t>(k);
    if (std::isfinite(bounds.s_hi[u])) hi.push_back({k * dt, bounds.s_hi[u]});
    lo.push_back({k * dt, bounds.s_lo[u]});
    ref.push_back({k * dt, bounds.s_ref[u]});
  }
  for (const auto& p : plan.trajectory) s.push_back({p.t, p.s - planner.path_start()});
  c.polyline(hi, Style("#000000", "none", 1.2, 1, "5 3"));
  c.polyline(lo, Style("#777777", "none", 1.0, 1, "2 3"));
  c.polyline(ref, Style(svg::colour::kReference, "none", 1, 1, "6 4"));
  c.polyline(s, Style(kPath, "none", 2.5));
  c.end_clip();
  const std::vector<svg::LegendEntry> legend{
      {"obstacle conflict zone", Style("none", svg::colour::kDynamic, 0, 0.35), true},
      {"s upper bound", Style("#000000", "none", 1.2, 1, "5 3"), false},
      {"s_up reference", Style(svg::colour::kReference, "none", 1, 1, "6 4"), false},
      {"speed QP s(t)", Style(kPath, "none", 2.5), false}};
  c.legend(legend);
  return c.str();
}

#define HIL_SIM_INSTANTIATE_PLOTS(Cfg)                                                                        \
  template std::string plot_sl<Cfg>(const itp::planner::BasicPlanner<Cfg>&, const itp::scene::BasicScene<Cfg>&, \
                                    const std::string&);                                                      \
  template std::string plot_xy<Cfg>(const itp::planner::BasicPlanner<Cfg>&, const itp::scene::BasicScene<Cfg>&, \
                                    const itp::planner::BasicPlan<Cfg>&, double, const std::string&);          \
  template std::string plot_st<Cfg>(const itp::planner::BasicPlanner<Cfg>&, const itp::planner::BasicPlan<Cfg>&, \
                                    const std::string&);
HIL_SIM_FOR_EACH_CONFIG(HIL_SIM_INSTANTIATE_PLOTS)
#undef HIL_SIM_INSTANTIATE_PLOTS

std::string stack_svgs(const std::vector<std::string>& svgs) {
  double width = 0;
  double y = 0;
  std::string body;
  const std::regex size(R"re(width="(\d+)" height="(\d+)")re");
  for (std::size_t i = 0; i < svgs.size(); ++i) {
    std::smatch m;
    if (!std::regex_search(svgs[i], m, size)) continue;
    const double w = std::stod(m[1].str());
    const double h = std::stod(m[2].str());
    std::string part = svgs[i];
    // Each part has its own clip path: give it a unique id.
    const std::string id = fmt::format("plot{}", i);
    part = std::regex_replace(part, std::regex(R"(id="plot")"), "id=\"" + id + "\"");
    part = std::regex_replace(part, std::regex(R"(url\(#plot\))"), "url(#" + id + ")");
    part.replace(0, 4, fmt::format("<svg x=\"0\" y=\"{:.0f}\"", y));
    body += part;
    width = std::max(width, w);
    y += h;
  }
  return fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:.0f}\" height=\"{1:.0f}\" "
                     "viewBox=\"0 0 {0:.0f} {1:.0f}\">\n{2}</svg>\n", width, y, body);
}

}  // namespace hil::sim
