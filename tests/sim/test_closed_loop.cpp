// The closed loop on the inproc target: physical outcomes of whole runs
// (no timing assertions), determinism, link-error handling, report/1 keys.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include <nlohmann/json.hpp>

#include "sim/closed_loop.hpp"
#include "sim/inproc_endpoint.hpp"
#include "sim/scene_plots.hpp"
#include "sim/scene_generator.hpp"
#include "sim/summary_table.hpp"

using namespace hil::sim;

namespace {

// Straight two-lane road along +x, the ego in the right lane (the reference line).
World straight_road(double length, double v0, double limit) {
  World w;
  w.name = "test-straight";
  for (double x = 0.0; x <= length + 1e-9; x += 2.0) w.reference_line.push_back({x, 0.0});
  w.road.lane_width = 3.5;
  w.road.left_boundary = Boundary::constant_at(5.25);
  w.road.right_boundary = Boundary::constant_at(-1.75);
  w.road.speed_limit = limit;
  w.ego.v = v0;
  return w;
}

// An endpoint whose every reply is lost.
class DeadEndpoint final : public PlannerEndpoint {
 public:
  void reset() override {}
  EndpointResult plan(const itp::scene::Scene&, double, itp::planner::Plan&) override {
    EndpointResult r;
    r.error = "no reply (timeout)";
    return r;
  }
  std::string name() const override { return "dead"; }
};

double final_speed(const SceneRunResult& r) { return r.trace.empty() ? -1.0 : r.trace.back().v; }

// The in-process planner until cycle `good`, then every reply is lost.
class FailingEndpoint final : public PlannerEndpoint {
 public:
  explicit FailingEndpoint(int good) : good_(good) {}
  void reset() override { inner_.reset(); }
  EndpointResult plan(const itp::scene::Scene& scene, double now, itp::planner::Plan& out) override {
    if (cycle_++ >= good_) {
      EndpointResult r;
      r.error = "lost";
      return r;
    }
    const EndpointResult r = inner_.plan(scene, now, out);
    last_ = out;
    last_now_ = now;
    return r;
  }
  std::string name() const override { return "failing"; }
  itp::planner::Plan last_;  // the last plan delivered
  double last_now_ = 0.0;

 private:
  InprocEndpoint inner_;
  int good_;
  int cycle_ = 0;
};

}  // namespace

TEST_CASE("closed loop: free straight road for 6 s, no collision or departure, speeds up to the limit") {
  const World w = straight_road(300.0, 8.0, 15.0);
  InprocEndpoint ep;
  RunOptions opt;
  opt.duration = 6.0;
  const SceneRunResult r = run_scene(w, ep, opt);
  const SceneSummary& s = r.summary;
  CHECK(r.error.empty());
  CHECK(s.steps == 61);
  CHECK(s.cycles == 60);
  CHECK_FALSE(s.collided());
  CHECK_FALSE(s.departed());
  CHECK(s.fallbacks == 0);
  CHECK(s.invalid_inputs == 0);
  CHECK(s.link_errors == 0);
  CHECK_FALSE(s.min_clearance_m.has_value());  // no obstacle at all
  CHECK(s.progress_m > 50.0);
  CHECK(final_speed(r) > 14.0);
  CHECK(final_speed(r) < 15.5);
  CHECK(s.max_abs_lateral_offset < 0.1);
  CHECK(r.trace.size() == 61);
  MESSAGE("free road: progress " << s.progress_m << " m, final v " << final_speed(r) << " m/s");
}

TEST_CASE("closed loop: a static obstacle in the lane is passed with clearance > 0.2 m") {
  World w = straight_road(300.0, 10.0, 12.0);
  w.static_obstacles.push_back(StaticObstacle{1, 60.0, 0.3, 0.0, 4.5, 1.8, "parked_car"});
  InprocEndpoint ep;
  RunOptions opt;
  opt.duration = 9.0;
  const SceneRunResult r = run_scene(w, ep, opt);
  const SceneSummary& s = r.summary;
  CHECK(r.error.empty());
  CHECK_FALSE(s.collided());
  CHECK_FALSE(s.departed());
  REQUIRE(s.min_clearance_m.has_value());
  CHECK(*s.min_clearance_m > 0.2);
  // Passed: the ego's rear axle ends well beyond the obstacle's front.
  CHECK(r.trace.back().pose.x > 60.0 + 2.25 + 10.0);
  // It went round on the left.
  double max_y = 0.0;
  for (const auto& e : r.trace) max_y = std::max(max_y, e.pose.y);
  CHECK(max_y > 1.5);
  MESSAGE("static obstacle: min clearance " << *s.min_clearance_m << " m, max y " << max_y << " m, fallbacks "
                                            << s.fallbacks);
}

TEST_CASE("closed loop: generated scene paper-0000 (seed 1) runs without collision, deterministically") {
  const World w = generate_scene(1, 0);
  InprocEndpoint ep;
  RunOptions opt;
  opt.keep_snapshot = true;
  const SceneRunResult a = run_scene(w, ep, opt);
  CHECK(a.error.empty());
  CHECK(a.summary.cycles == 120);
  CHECK_FALSE(a.summary.collided());
  CHECK_FALSE(a.summary.departed());
  CHECK(a.summary.invalid_inputs == 0);
  CHECK(a.summary.progress_m > 30.0);
  REQUIRE_FALSE(a.snapshots.empty());
  CHECK_FALSE(a.snapshots.back().scenes.empty());

  // Same endpoint object again (reset between scenes): bit-identical run.
  const SceneRunResult b = run_scene(w, ep, opt);
  REQUIRE(a.trace.size() == b.trace.size());
  bool same = true;
  for (std::size_t i = 0; i < a.trace.size(); ++i) {
    same = same && a.trace[i].pose.x == b.trace[i].pose.x && a.trace[i].pose.y == b.trace[i].pose.y &&
           a.trace[i].v == b.trace[i].v;
  }
  CHECK(same);
  CHECK(a.summary.fallbacks == b.summary.fallbacks);
  CHECK(a.summary.iterations == b.summary.iterations);

  // The per-scene SVG renders (XY, charts and the re-planned snapshot cycle).
  const std::string svg = scene_run_svg(w, a);
  CHECK(svg.rfind("<svg", 0) == 0);
  CHECK(svg.find("re-planned in-process") != std::string::npos);
}

TEST_CASE("closed loop: lost replies are link errors and the ego brakes to a stop") {
  const World w = straight_road(200.0, 8.0, 15.0);
  DeadEndpoint ep;
  RunOptions opt;
  opt.duration = 4.0;
  const SceneRunResult r = run_scene(w, ep, opt);
  CHECK(r.summary.link_errors == 40);
  CHECK(r.summary.cycles == 0);
  CHECK(final_speed(r) == 0.0);
  CHECK(r.summary.max_abs_lon_acc == doctest::Approx(opt.emergency_decel));
  // Stopping distance at the emergency rate.
  CHECK(r.summary.progress_m == doctest::Approx(8.0 * 8.0 / (2.0 * opt.emergency_decel)).epsilon(0.02));
}

// Issue 13: when plans stop arriving the ego follows the last valid plan
// while it lasts, then stands still at its end (it used to brake where it was
// at the first lost reply).
TEST_CASE("closed loop: plans lost after 2 s: the ego follows the last plan and stops by its end, on its path") {
  const World w = straight_road(400.0, 12.0, 15.0);
  FailingEndpoint ep(20);
  RunOptions opt;
  opt.duration = 12.0;
  const SceneRunResult r = run_scene(w, ep, opt);
  CHECK(r.summary.link_errors == 100);
  REQUIRE_FALSE(ep.last_.trajectory.empty());
  const auto& last = ep.last_.trajectory;
  // Where the last plan ends: the ego stands still there or before, near its path.
  const auto& end = last.back();
  const auto& stop = r.trace.back();
  CHECK(final_speed(r) < 0.05);
  CHECK(stop.pose.x <= end.x + 0.5);
  CHECK(std::fabs(stop.pose.y - end.y) < 0.5);
  // It kept driving for a while after the loss (the plan still held), not a
  // stop right at the first lost cycle: beyond the emergency stopping distance.
  const double x_at_loss = r.trace[20].pose.x;
  const double v_at_loss = r.trace[20].v;
  CHECK(stop.pose.x - x_at_loss > v_at_loss * v_at_loss / (2.0 * opt.emergency_decel) + 5.0);
  // It stood still by the plan's end time (last plan started at 1.9 s, lasts 7 s).
  for (const auto& e : r.trace) {
    if (e.t >= ep.last_now_ + last.back().t + 0.05) CHECK(e.v < 0.05);
  }
  CHECK_FALSE(r.summary.collided());
  CHECK_FALSE(r.summary.departed());
}

TEST_CASE("closed loop: report/1 from the suite aggregator has every required key") {
  const World w = straight_road(300.0, 8.0, 15.0);
  InprocEndpoint ep;
  RunOptions opt;
  opt.duration = 2.0;
  SuiteAggregator suite;
  suite.add(run_scene(w, ep, opt).summary);
  const nlohmann::json rep = suite.report(ep.name());
  for (const char* key : {"format", "target", "scenes", "cycles", "collisions", "road_departures", "fallbacks",
                          "invalid_inputs", "link_errors", "crashes", "min_clearance_m", "max_abs_lat_acc",
                          "max_abs_lon_acc", "iterations", "cycle_time_us", "instructions_per_cycle", "per_scene"}) {
    CHECK_MESSAGE(rep.contains(key), key);
  }
  CHECK(rep["format"] == "report/1");
  CHECK(rep["target"] == "inproc");
  CHECK(rep["scenes"] == 1);
  CHECK(rep["cycles"] == 20);
  CHECK(rep["iterations"].contains("mean"));
  CHECK(rep["iterations"].contains("max"));
  for (const char* k : {"median", "p99", "max"}) CHECK(rep["cycle_time_us"].contains(k));
  CHECK(rep["cycle_time_us"]["median"].is_number());  // inproc measures its time
  CHECK(rep["instructions_per_cycle"]["median"].is_null());
  REQUIRE(rep["per_scene"].size() == 1);
  CHECK(rep["per_scene"][0]["name"] == "test-straight");
  CHECK(rep["per_scene"][0].contains("collisions"));
  CHECK(rep["per_scene"][0].contains("fallbacks"));
  CHECK(rep["per_scene"][0].contains("min_clearance_m"));
  const std::string table = summary_table(rep);
  CHECK(table.find("collisions") != std::string::npos);
}

namespace {

// The inproc planner, with every cycle's decision-stage runs and status seen.
class CountingEndpoint final : public PlannerEndpoint {
 public:
  void reset() override { inner_.reset(); }
  EndpointResult plan(const itp::scene::Scene& scene, double now, itp::planner::Plan& out) override {
    const EndpointResult r = inner_.plan(scene, now, out);
    max_runs = std::max(max_runs, out.timing.decision_runs);
    if (out.timing.decision_runs == itp::DefaultConfig::kMaxDecisionRunsPerCycle) {
      ++at_budget;
      ok_at_budget += out.status == itp::PlanStatus::kOk ? 1 : 0;
    }
    return r;
  }
  std::string name() const override { return "counting"; }
  int max_runs = 0;
  int at_budget = 0;     // cycles that used the whole budget
  int ok_at_budget = 0;  // ... and still planned ok (the last run succeeded)

 private:
  InprocEndpoint inner_;
};

}  // namespace

TEST_CASE("closed loop: cycles that reach the decision-stage budget stay within it and stay safe") {
  // Generated scenes whose cycles need more decision-stage runs than the
  // budget (kMaxDecisionRunsPerCycle) allows: without it some cycles ran 30
  // (5 iterations x 6 rounds). The scenes were found by scanning seeds 1, 5
  // and 7 (at-budget cycles per scene at the time: 16, 5, 5, 3); the test
  // needs the budget to be reached in at least one of them (pick others if
  // the planner no longer needs it there).
  int at_budget = 0;
  int ok_at_budget = 0;
  for (const auto& [seed, index] : {std::pair{5, 163}, std::pair{5, 178}, std::pair{1, 193}, std::pair{1, 186}}) {
    const World w = generate_scene(static_cast<std::uint64_t>(seed), index);
    CountingEndpoint ep;
    const SceneRunResult r = run_scene(w, ep, RunOptions{});
    CAPTURE(w.name);
    CHECK(r.error.empty());
    CHECK(ep.max_runs <= itp::DefaultConfig::kMaxDecisionRunsPerCycle);
    CHECK_FALSE(r.summary.collided());
    CHECK_FALSE(r.summary.departed());
    at_budget += ep.at_budget;
    ok_at_budget += ep.ok_at_budget;
  }
  CHECK(at_budget > 0);
  MESSAGE("cycles at the decision budget: " << at_budget << " (" << ok_at_budget << " still ok)");
}

namespace {

// The inproc planner, with every cycle's work checked against the per-cycle
// budgets and every budget fallback's plan checked to be a stop.
class BudgetEndpoint final : public PlannerEndpoint {
 public:
  void reset() override { inner_.reset(); }
  EndpointResult plan(const itp::scene::Scene& scene, double now, itp::planner::Plan& out) override {
    using C = itp::DefaultConfig;
    const EndpointResult r = inner_.plan(scene, now, out);
    const itp::planner::StageTiming& w = out.timing;
    within &= w.decision_runs <= C::kMaxDecisionRunsPerCycle && w.tree_nodes <= C::kMaxTreeNodesPerCycle &&
              w.coarse_qps <= C::kMaxCoarseQpsPerCycle && w.coarse_iterations <= C::kMaxCoarseIterationsPerCycle &&
              w.path_solves <= C::kMaxPathSolvesPerCycle && w.path_iterations <= C::kMaxPathIterationsPerCycle &&
              w.speed_solves <= C::kMaxSpeedSolvesPerCycle && w.speed_iterations <= C::kMaxSpeedIterationsPerCycle;
    // The QP stages' shared work, recomputed from the counts the plan reports.
    const long qp_work = static_cast<long>(w.coarse_qps) * C::kCoarseQpSetupWork +
                         static_cast<long>(w.coarse_iterations) * C::kCoarseIterationWork +
                         static_cast<long>(w.path_solves) * C::kPathSolveSetupWork +
                         static_cast<long>(w.path_iterations) * C::kPathIterationWork +
                         static_cast<long>(w.speed_solves) * C::kSpeedSolveSetupWork +
                         static_cast<long>(w.speed_iterations) * C::kSpeedIterationWork;
    within &= qp_work <= C::kQpWorkPerCycle;
    max_qp_work = std::max(max_qp_work, qp_work);
    if (out.status == itp::PlanStatus::kFallback && out.fallback == itp::planner::FallbackReason::kBudget) {
      ++budget_fallbacks;
      bool stop = !out.trajectory.empty();
      for (std::size_t k = 1; k < out.trajectory.size(); ++k) {
        stop &= out.trajectory[k].v <= out.trajectory[k - 1].v + 1e-6;  // never speeds up
      }
      stops += stop ? 1 : 0;
    }
    return r;
  }
  std::string name() const override { return "budget"; }
  bool within = true;
  long max_qp_work = 0;  // [k instructions] the most QP work a cycle charged
  int budget_fallbacks = 0;
  int stops = 0;  // ... whose trajectory is a stop (speed never rising)

 private:
  InprocEndpoint inner_;
};

}  // namespace

TEST_CASE("closed loop: every cycle stays within its budgets, and a spent budget falls back to a stop (reason budget)") {
  // Generated scenes in which the budgets of itp/config.hpp run out in some
  // cycles (found from the seeds 1-10 traces: reason "budget"; pick others if
  // the planner no longer needs that much work there).
  int budget_fallbacks = 0;
  int stops = 0;
  long max_qp_work = 0;
  for (const auto& [seed, index] : {std::pair{9, 127}, std::pair{2, 53}, std::pair{5, 72}}) {
    const World w = generate_scene(static_cast<std::uint64_t>(seed), index);
    BudgetEndpoint ep;
    const SceneRunResult r = run_scene(w, ep, RunOptions{});
    CAPTURE(w.name);
    CHECK(r.error.empty());
    CHECK(ep.within);
    CHECK_FALSE(r.summary.collided());
    CHECK_FALSE(r.summary.departed());
    budget_fallbacks += ep.budget_fallbacks;
    stops += ep.stops;
    max_qp_work = std::max(max_qp_work, ep.max_qp_work);
  }
  CHECK(budget_fallbacks > 0);
  CHECK(stops == budget_fallbacks);
  MESSAGE("budget fallbacks: " << budget_fallbacks << ", most QP work in a cycle: " << max_qp_work << " of "
                               << itp::DefaultConfig::kQpWorkPerCycle << " k instructions");
}

TEST_CASE("closed loop: more traffic in range than the scene holds never ends the run, and what was left out is counted") {
  World w = straight_road(400.0, 10.0, 15.0);
  w.road.left_boundary = Boundary::constant_at(8.75);  // three lanes
  // 9 cars in the two left lanes, all in range, driving along: 4 more than the default scene holds.
  for (int i = 0; i < 9; ++i) {
    DynamicObstacle d;
    d.id = 20 + i;
    d.length = 4.5;
    d.width = 1.8;
    const double y = i % 2 == 0 ? 3.5 : 7.0;
    d.trajectory.push_back({0.0, 15.0 + 12.0 * i, y, 0.0, 10.0});
    w.dynamic_obstacles.push_back(d);
  }
  InprocEndpoint ep;
  RunOptions opt;
  opt.duration = 3.0;
  const SceneRunResult r = run_scene(w, ep, opt);
  CHECK(r.error.empty());
  CHECK_FALSE(r.summary.crashed);
  CHECK(r.summary.cycles == 30);
  CHECK(r.summary.left_out_cycles == 30);
  CHECK(r.summary.left_out_max == 9 - itp::DefaultConfig::kMaxDynamicObstacles);
  CHECK(r.summary.left_out_total == 30 * (9 - itp::DefaultConfig::kMaxDynamicObstacles));
  REQUIRE_FALSE(r.cycles.empty());
  CHECK(r.cycles.front().left_out == 4);
  SuiteAggregator suite;
  suite.add(r.summary);
  const nlohmann::json rep = suite.report(ep.name());
  CHECK(rep["crashes"] == 0);
  REQUIRE(rep.contains("obstacles_left_out"));
  CHECK(rep["obstacles_left_out"]["total"] == 120);
  CHECK(rep["per_scene"][0]["obstacles_left_out"]["cycles"] == 30);
}

namespace {

// The in-process planner of configuration Cfg, counting the objects of the
// Scenes it is given.
template <class Cfg>
class ObjectCountingEndpoint final : public BasicPlannerEndpoint<Cfg> {
 public:
  void reset() override { inner_.reset(); }
  EndpointResult plan(const itp::scene::BasicScene<Cfg>& scene, double now, itp::planner::BasicPlan<Cfg>& out) override {
    const int n = static_cast<int>(scene.static_obstacles.size() + scene.dynamic_obstacles.size());
    min_objects = std::min(min_objects, n);
    max_objects = std::max(max_objects, n);
    return inner_.plan(scene, now, out);
  }
  std::string name() const override { return "counting"; }
  int min_objects = 1 << 30;
  int max_objects = 0;

 private:
  BasicInprocEndpoint<Cfg> inner_;
};

}  // namespace

TEST_CASE("closed loop --config road: 24 objects in range are all planned with; the default configuration leaves 9 out") {
  // A three-lane road with 14 cars parked beside it (off the drivable area,
  // all within range) and 10 cars driving along the two left lanes: 24
  // objects, more than the default scene's 10 + 5, fewer than the road
  // configuration's 32 + 32.
  World w = straight_road(500.0, 10.0, 15.0);
  w.road.left_boundary = Boundary::constant_at(8.75);
  for (int i = 0; i < 14; ++i) {
    w.static_obstacles.push_back({1 + i, 20.0 + 9.0 * i, -3.3, 0.0, 4.5, 1.8, "parked_car"});
  }
  for (int i = 0; i < 10; ++i) {
    DynamicObstacle d;
    d.id = 40 + i;
    d.length = 4.5;
    d.width = 1.8;
    d.trajectory.push_back({0.0, 10.0 + 11.0 * i, i % 2 == 0 ? 3.5 : 7.0, 0.0, 11.0});
    w.dynamic_obstacles.push_back(d);
  }
  RunOptions opt;
  opt.duration = 3.0;

  ObjectCountingEndpoint<itp::RoadConfig> road;
  const SceneRunResult r = run_scene(w, road, opt);
  CHECK(r.error.empty());
  CHECK(r.summary.cycles == 30);
  CHECK(r.summary.left_out_cycles == 0);
  CHECK(r.summary.left_out_total == 0);
  CHECK_FALSE(r.summary.collided());
  CHECK_FALSE(r.summary.departed());
  // Every cycle's Scene held all 24.
  CHECK(road.min_objects == 24);
  CHECK(road.max_objects == 24);

  ObjectCountingEndpoint<itp::DefaultConfig> def;
  const SceneRunResult d = run_scene(w, def, opt);
  CHECK(d.error.empty());
  CHECK(d.summary.left_out_cycles == 30);
  CHECK(d.summary.left_out_max == (14 - itp::DefaultConfig::kMaxStaticObstacles) + (10 - itp::DefaultConfig::kMaxDynamicObstacles));
  REQUIRE_FALSE(d.cycles.empty());
  CHECK(d.cycles.front().left_out == 9);
  CHECK(def.max_objects == 15);
}

TEST_CASE("closed loop --config road: snapshots hold road scenes and the plots re-plan them with the road planner") {
  World w = generate_scene(1, 0);
  BasicInprocEndpoint<itp::RoadConfig> ep;
  RunOptions opt;
  opt.duration = 2.0;
  opt.keep_snapshot = true;
  const SceneRunResult r = run_scene(w, ep, opt);
  CHECK(r.error.empty());
  REQUIRE_FALSE(r.snapshots.empty());
  REQUIRE_FALSE(r.snapshots.back().scenes.empty());
  CHECK(std::holds_alternative<SceneRef<itp::RoadConfig>>(r.snapshots.back().scenes.back().second));
  const std::string svg = scene_run_svg(w, r);
  CHECK(svg.find("re-planned in-process") != std::string::npos);
}
