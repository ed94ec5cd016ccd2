// Metrics accumulator, report/1 writer, and the SVG/HTML helpers (smoke).
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sim/metrics.hpp"
#include "sim/scene_generator.hpp"
#include "sim/svg.hpp"

using namespace hil::sim;

namespace {
StepSample step(double t, double ego_x, double obstacle_x) {
  StepSample x;
  x.t = t;
  x.ego = OrientedBox{ego_x, 0.0, 0.0, 4.8, 1.9};
  x.obstacles = {OrientedBox{obstacle_x, 0.0, 0.0, 4.0, 1.8}};
  x.progress_s = ego_x;
  x.road_margin = 1.0;
  return x;
}
}  // namespace

TEST_CASE("metrics: collisions, clearance, departures, fallbacks, comfort, plan consistency") {
  SceneMetrics m("paper-0001", {"road:straight"});
  StepSample a = step(0.0, 0.0, 10.0);  // gap 10 - 2 - 2.4 = 5.6
  a.status = itp::PlanStatus::kOk;
  a.iterations = 3;
  a.cycle_time_us = 400.0;
  a.a_lon = 1.0;
  m.add_step(a);
  StepSample b = step(0.1, 5.0, 8.0);  // overlapping
  b.status = itp::PlanStatus::kFallback;
  b.reason = "no_feasible_decision";
  b.iterations = 5;
  b.cycle_time_us = 900.0;
  b.a_lon = -1.0;  // jerk 20 m/s^3
  b.a_lat = -2.5;
  b.road_margin = -0.2;
  m.add_step(b);
  StepSample c = step(0.2, 6.0, 20.0);
  c.status = itp::PlanStatus::kInvalidInput;
  c.reason = "reference_line_too_short";
  m.add_step(c);
  m.add_link_error();

  std::vector<TrajectoryPoint> p1, p2;
  for (int k = 0; k <= 70; ++k) {
    p1.push_back({k * 0.1, k * 1.0, 0.0, 0.0, 0.0, 10.0, 0.0});
    p2.push_back({k * 0.1, 1.0 + k * 1.0, 0.3, 0.0, 0.0, 10.0, 0.0});  // 0.1 s later, 0.3 m left
  }
  CHECK(m.add_plan(0.0, p1) < 0);                        // nothing to compare with yet
  CHECK(m.add_plan(0.1, p2) == doctest::Approx(0.3));     // a parallel path 0.3 m to the left

  const SceneSummary& s = m.summary();
  CHECK(s.steps == 3);
  CHECK(s.cycles == 3);
  CHECK(s.collision_steps == 1);
  CHECK(s.collided());
  REQUIRE(s.min_clearance_m.has_value());
  CHECK(*s.min_clearance_m == 0.0);
  CHECK(s.road_departure_steps == 1);
  CHECK(s.max_road_excess_m == doctest::Approx(0.2));
  CHECK(s.fallbacks == 1);
  CHECK(s.fallback_reasons.at("no_feasible_decision") == 1);
  CHECK(s.invalid_inputs == 1);
  CHECK(s.link_errors == 1);
  CHECK(s.progress_m == doctest::Approx(6.0));
  CHECK(s.max_abs_jerk == doctest::Approx(20.0));
  CHECK(s.max_abs_lat_acc == doctest::Approx(2.5));
  REQUIRE(s.max_plan_deviation_m.has_value());
  CHECK(*s.max_plan_deviation_m == doctest::Approx(0.3));
}

TEST_CASE("metrics: a collision is the ego running into something or being hit, by closing speed") {
  const OrientedBox ego{0.0, 0.0, 0.0, 4.8, 1.9};
  const OrientedBox ahead{4.5, 0.0, 0.0, 4.0, 1.8};
  const OrientedBox behind{-4.5, 0.0, 0.0, 4.0, 1.8};
  // Into a standing car ahead; into a slower one; a faster follower into a
  // standing ego; a faster follower into a moving ego; a car from the left
  // side into a standing ego.
  CHECK(who_ran_into(ego, {10, 0}, ahead, {0, 0}) == SceneSummary::CollisionKind::kRanInto);
  CHECK(who_ran_into(ego, {10, 0}, ahead, {6, 0}) == SceneSummary::CollisionKind::kRanInto);
  CHECK(who_ran_into(ego, {0, 0}, behind, {8, 0}) == SceneSummary::CollisionKind::kHit);
  CHECK(who_ran_into(ego, {5, 0}, behind, {9, 0}) == SceneSummary::CollisionKind::kHit);
  CHECK(who_ran_into(ego, {0, 0}, OrientedBox{0.0, 2.5, -1.57, 4.0, 1.8}, {0, -3}) ==
        SceneSummary::CollisionKind::kHit);
  // In a run: the first contact's kind is the scene's, in the report too.
  SceneMetrics m("rear-end");
  StepSample x = step(0.0, 0.0, -10.0);
  x.obstacle_velocities = {Point2{8, 0}};
  m.add_step(x);
  x = step(0.1, 0.0, -4.0);
  x.obstacle_velocities = {Point2{8, 0}};
  m.add_step(x);
  CHECK(m.summary().collision_kind == SceneSummary::CollisionKind::kHit);
  SuiteAggregator agg;
  agg.add(m.summary());
  const nlohmann::json rep = agg.report("inproc");
  CHECK(rep["collisions"] == 1);
  CHECK(rep["collisions_hit"] == 1);
  CHECK(rep["collisions_ran_into"] == 0);
  CHECK(rep["per_scene"][0]["collision_kind"] == "hit");
}

TEST_CASE("stats: median, nearest-rank p99, max") {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);
  const Stats st = compute_stats(v);
  CHECK(*st.median == doctest::Approx(50.5));
  CHECK(*st.p99 == doctest::Approx(99.0));
  CHECK(*st.max == doctest::Approx(100.0));
  CHECK_FALSE(compute_stats({}).median.has_value());
}

TEST_CASE("report/1: every required key, null for what the target cannot measure") {
  SuiteAggregator suite;
  for (int k = 0; k < 2; ++k) {
    SceneMetrics m(fmt::format("paper-{:04d}", k));
    StepSample x = step(0.0, 0.0, 10.0);
    x.status = itp::PlanStatus::kOk;
    x.iterations = 2 + k;
    x.instructions = 2.0e6 * (k + 1);  // qemu: instructions, no host clock
    m.add_step(x);
    suite.add(m.summary());
  }
  const nlohmann::json r = suite.report("qemu");
  for (const char* key : {"format", "target", "scenes", "cycles", "collisions", "road_departures",
                          "fallbacks", "invalid_inputs", "link_errors", "crashes", "min_clearance_m",
                          "max_abs_lat_acc", "max_abs_lon_acc", "iterations", "cycle_time_us",
                          "instructions_per_cycle", "per_scene"}) {
    CAPTURE(key);
    CHECK(r.contains(key));
  }
  CHECK(r["format"] == "report/1");
  CHECK(r["target"] == "qemu");
  CHECK(r["scenes"] == 2);
  CHECK(r["cycles"] == 2);
  CHECK(r["collisions"] == 0);
  CHECK(r["iterations"]["mean"].get<double>() == doctest::Approx(2.5));
  CHECK(r["iterations"]["max"] == 3);
  for (const char* k : {"median", "p99", "max"}) CHECK(r["cycle_time_us"][k].is_null());
  CHECK(r["instructions_per_cycle"]["median"].get<double>() == doctest::Approx(3.0e6));
  CHECK(r["instructions_per_cycle"]["max"].get<double>() == doctest::Approx(4.0e6));
  CHECK(r["min_clearance_m"].get<double>() == doctest::Approx(5.6));
  REQUIRE(r["per_scene"].size() == 2);
  for (const char* k : {"name", "collisions", "fallbacks", "min_clearance_m"}) CHECK(r["per_scene"][0].contains(k));

  const nlohmann::json empty = SuiteAggregator{}.report("host");
  CHECK(empty["scenes"] == 0);
  CHECK(empty["min_clearance_m"].is_null());
  CHECK(empty["iterations"]["mean"].is_null());
}

TEST_CASE("road margin: corners inside the boundaries are positive, outside negative") {
  std::vector<Point2> ref;
  for (int i = 0; i <= 50; ++i) ref.push_back({2.0 * i, 0.0});
  Road road;
  road.left_boundary = Boundary::constant_at(5.25);
  road.right_boundary = Boundary::constant_at(-1.75);
  CHECK(road_margin(ref, road, OrientedBox{20, 0, 0, 4.8, 1.9}) == doctest::Approx(0.8));
  CHECK(road_margin(ref, road, OrientedBox{20, -1.2, 0, 4.8, 1.9}) == doctest::Approx(-0.4));
}

TEST_CASE("svg: scene view, line chart and index page are well-formed") {
  const World w = generate_scene(1, 5);
  std::vector<svg::EgoTraceSample> trace;
  for (int k = 0; k <= 120; ++k) trace.push_back({k * 0.1, Pose{k * 0.1 * w.ego.v, 0.0, 0.0}, w.ego.v});
  const std::string xy = svg::plot_scene_xy(w, trace);
  CHECK(xy.rfind("<svg", 0) == 0);
  CHECK(xy.find("</svg>") != std::string::npos);
  CHECK(xy.find(w.name) != std::string::npos);
  CHECK(xy.find("<polygon") != std::string::npos);
  CHECK(xy == svg::plot_scene_xy(w, trace));  // deterministic

  const svg::Series series[] = {{"v", {{0, 10}, {1, 11}, {2, 12}}, "", false},
                                {"v_ref", {{0, 12}, {2, 12}}, "", true}};
  const std::string chart = svg::plot_line_chart("speed <ego>", "t [s]", "v [m/s]", series);
  CHECK(chart.find("speed &lt;ego&gt;") != std::string::npos);
  CHECK(chart.find("stroke-dasharray") != std::string::npos);

  const svg::IndexRow rows[] = {{"paper-0000", true, {{"xy", "paper-0000.svg"}}, {{"collisions", "0"}}},
                                {"paper-0001", false, {{"xy", "paper-0001.svg"}}, {{"collisions", "1"}}}};
  const std::string lines[] = {"200 scenes"};
  const std::string html = svg::index_html("hil_sim report", lines, rows);
  CHECK(html.find("<th>collisions</th>") != std::string::npos);
  CHECK(html.find("href=\"paper-0001.svg\"") != std::string::npos);
  CHECK(html.find("class=\"bad\"") != std::string::npos);
}

TEST_CASE("path deviation ignores speed changes along the same path and measures lateral jumps") {
  SceneMetrics m("paths");
  std::vector<TrajectoryPoint> fast, slow, swerve;
  for (int k = 0; k <= 70; ++k) {
    const double t = k * 0.1;
    fast.push_back({t, 10.0 * t, 0.0, 0.0, 0.0, 10.0, 0.0});
    slow.push_back({t, 1.0 + 5.0 * t, 0.0, 0.0, 0.0, 5.0, 0.0});  // same line, half the speed
    // The same line, then a lateral step of 1.2 m from x = 20 m on.
    const double x = 1.5 + 5.0 * t;
    swerve.push_back({t, x, x > 20.0 ? 1.2 : 0.0, 0.0, 0.0, 5.0, 0.0});
  }
  m.add_plan(0.0, fast);
  CHECK(m.add_plan(0.1, slow) == doctest::Approx(0.0).epsilon(1e-9));
  CHECK(m.add_plan(0.2, swerve) == doctest::Approx(1.2));
  REQUIRE(m.summary().max_path_deviation_m.has_value());
  CHECK(*m.summary().max_path_deviation_m == doctest::Approx(1.2));
}
