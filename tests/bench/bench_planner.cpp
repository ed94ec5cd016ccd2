// Google Benchmark of the planner (docs/performance.md): the full cycle over
// generated scenes of the paper's envelope, and the decision stage on the
// busiest scenes (10 static + 5 dynamic obstacles), and the steady state of a
// planner running at 10 Hz (stitched cycles); the same first cycles with the
// road configuration (RoadConfig: a 32 + 32 object list), as they are and with
// 16 parked cars and 8 cars on a parallel road added. Timing is measured
// here, never asserted in tests.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <memory>
#include <numeric>
#include <vector>

#include "itp/configurations.hpp"
#include "itp/planner/planner.hpp"
#include "sim/scene_convert.hpp"
#include "sim/scene_generator.hpp"

namespace {

constexpr std::uint64_t kSeed = 2026;
constexpr int kEnvelopeScenes = 120;
constexpr int kBusyScenes = 40;

// The planner's per-stage timing reads this thread's CPU time, not the wall
// clock: on a shared machine a wall-clock maximum is mostly the time the
// thread was not running (a lost time slice is 4 ms); CPU time is what the
// cycle costs.
std::uint64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<std::uint64_t>(ts.tv_sec) * 1000000000u + static_cast<std::uint64_t>(ts.tv_nsec);
}

std::vector<itp::scene::Scene> make_scenes(int count, const hil::sim::GeneratorConfig& config) {
  std::vector<itp::scene::Scene> scenes;
  for (const hil::sim::World& w : hil::sim::default_suite(count, kSeed, config)) {
    scenes.emplace_back();
    if (!hil::sim::make_planner_scene(w, hil::sim::ego_at_start(w), 0.0, hil::sim::Prediction::kGroundTruth,
                                      scenes.back())
             .ok) {
      scenes.pop_back();
    }
  }
  return scenes;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

struct Samples {
  std::vector<double> total_us, decision_us, path_us, speed_us, check_us, prepare_us, decision_run_us;
  std::vector<double> iterations;
  int ok = 0, fallback = 0, invalid = 0;
};

template <class PlanT>
void record(const PlanT& plan, Samples& out) {
  const auto us = [](std::uint64_t ns) { return static_cast<double>(ns) / 1e3; };
  out.total_us.push_back(us(plan.timing.total));
  out.prepare_us.push_back(us(plan.timing.prepare));
  out.decision_us.push_back(us(plan.timing.decision));
  out.path_us.push_back(us(plan.timing.path));
  out.speed_us.push_back(us(plan.timing.speed));
  out.check_us.push_back(us(plan.timing.check));
  if (plan.timing.decision_runs > 0) {
    out.decision_run_us.push_back(us(plan.timing.decision) / plan.timing.decision_runs);
  }
  out.iterations.push_back(plan.iterations);
  out.ok += plan.status == itp::PlanStatus::kOk ? 1 : 0;
  out.fallback += plan.status == itp::PlanStatus::kFallback ? 1 : 0;
  out.invalid += plan.status == itp::PlanStatus::kInvalidInput ? 1 : 0;
}

template <class Cfg>
void plan_all(const std::vector<itp::scene::BasicScene<Cfg>>& scenes, itp::planner::BasicPlanner<Cfg>& planner,
              itp::planner::BasicPlan<Cfg>& plan, Samples& out) {
  for (const auto& s : scenes) {
    planner.reset();  // every scene is a first cycle: no stitching
    planner.plan(itp::planner::BasicPlanRequest<Cfg>{&s, 0.0}, plan);
    record(plan, out);
  }
}

void report(benchmark::State& state, const Samples& s) {
  const auto mean = [](const std::vector<double>& v) {
    return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  };
  state.counters["median_us"] = percentile(s.total_us, 0.5);
  state.counters["p99_us"] = percentile(s.total_us, 0.99);
  state.counters["max_us"] = percentile(s.total_us, 1.0);
  state.counters["decision_run_median_us"] = percentile(s.decision_run_us, 0.5);
  state.counters["decision_run_max_us"] = percentile(s.decision_run_us, 1.0);
  state.counters["share_prepare"] = mean(s.prepare_us) / mean(s.total_us);
  state.counters["share_decision"] = mean(s.decision_us) / mean(s.total_us);
  state.counters["share_path"] = mean(s.path_us) / mean(s.total_us);
  state.counters["share_speed"] = mean(s.speed_us) / mean(s.total_us);
  state.counters["share_check"] = mean(s.check_us) / mean(s.total_us);
  state.counters["iterations_mean"] = mean(s.iterations);
  state.counters["iterations_max"] = percentile(s.iterations, 1.0);
  state.counters["ok"] = s.ok;
  state.counters["fallback"] = s.fallback;
}

// Every pass plans the same cycles and the planner is deterministic, so the
// passes differ only by interference from the shared machine (cache and
// hyper-thread contention, which CPU time still includes): each cycle's cost
// is its fastest pass, and the counters give the distribution over cycles.
void keep_fastest(Samples& best, const Samples& pass, bool first) {
  if (first) {
    best = pass;
    return;
  }
  const auto fold = [](std::vector<double>& b, const std::vector<double>& p) {
    for (std::size_t i = 0; i < b.size() && i < p.size(); ++i) b[i] = std::min(b[i], p[i]);
  };
  fold(best.total_us, pass.total_us);
  fold(best.prepare_us, pass.prepare_us);
  fold(best.decision_us, pass.decision_us);
  fold(best.path_us, pass.path_us);
  fold(best.speed_us, pass.speed_us);
  fold(best.check_us, pass.check_us);
  fold(best.decision_run_us, pass.decision_run_us);
}

// One benchmark iteration = every scene planned once (a pass).
template <class Cfg>
void run_suite(benchmark::State& state, const std::vector<itp::scene::BasicScene<Cfg>>& scenes) {
  auto planner = std::make_unique<itp::planner::BasicPlanner<Cfg>>();
  auto plan = std::make_unique<itp::planner::BasicPlan<Cfg>>();
  planner->set_tick_source(itp::TickSource{&now_ns, 1000000000u});
  Samples samples;
  bool first = true;
  for (auto _ : state) {
    Samples one;
    plan_all(scenes, *planner, *plan, one);
    benchmark::DoNotOptimize(plan->trajectory.data());
    keep_fastest(samples, one, first);
    first = false;
  }
  report(state, samples);
}

void BM_FullCycle_Envelope(benchmark::State& state) {
  static const auto scenes = make_scenes(kEnvelopeScenes, hil::sim::GeneratorConfig{});
  run_suite(state, scenes);
}

// Steady state at 10 Hz: each scene is planned for kSteadyCycles cycles, the
// ego moved exactly along the last plan (perfect tracking), so every cycle
// after the first stitches from the previous plan as in the closed loop. Only
// those later cycles are measured: the distribution of a running planner.
constexpr int kSteadyCycles = 20;

void plan_steady(const std::vector<hil::sim::World>& worlds, itp::planner::Planner& planner,
                 itp::planner::Plan& plan, itp::scene::Scene& scene, Samples& out) {
  for (const hil::sim::World& w : worlds) {
    planner.reset();
    hil::sim::EgoNow ego = hil::sim::ego_at_start(w);
    for (int k = 0; k < kSteadyCycles; ++k) {
      const double now = 0.1 * k;
      if (!hil::sim::make_planner_scene(w, ego, now, hil::sim::Prediction::kGroundTruth, scene).ok) {
        break;
      }
      planner.plan(itp::planner::PlanRequest{&scene, now}, plan);
      if (k > 0) {
        record(plan, out);
      }
      const itp::planner::TrajectoryPoint& p = plan.trajectory[1];  // 0.1 s on
      ego = hil::sim::EgoNow{p.x, p.y, p.heading, p.v, p.a, p.kappa};
    }
  }
}

void BM_SteadyCycle_Envelope(benchmark::State& state) {
  static const auto worlds = hil::sim::default_suite(kEnvelopeScenes, kSeed, hil::sim::GeneratorConfig{});
  auto planner = std::make_unique<itp::planner::Planner>();
  auto plan = std::make_unique<itp::planner::Plan>();
  auto scene = std::make_unique<itp::scene::Scene>();
  planner->set_tick_source(itp::TickSource{&now_ns, 1000000000u});
  Samples samples;
  bool first = true;
  for (auto _ : state) {
    Samples one;
    plan_steady(worlds, *planner, *plan, *scene, one);
    benchmark::DoNotOptimize(plan->trajectory.data());
    keep_fastest(samples, one, first);
    first = false;
  }
  report(state, samples);
}

void BM_FullCycle_Busy_10s_5d(benchmark::State& state) {
  hil::sim::GeneratorConfig busy;
  busy.min_static = busy.max_static = 10;
  busy.min_dynamic = busy.max_dynamic = 5;
  static const auto scenes = make_scenes(kBusyScenes, busy);
  run_suite(state, scenes);
}

// The road configuration. A default scene in RoadConfig's capacities
// (predictions every 0.2 s), plus `parked` cars 2.5 m beyond the right road
// edge and `parallel` cars on a road 6 m beyond it (constant velocity along
// the reference line's local direction): objects the ST graph and the
// collision check see, the decision stage does not need.
using RoadScene = itp::scene::BasicScene<itp::RoadConfig>;

RoadScene to_road(const itp::scene::Scene& d, int parked, int parallel) {
  RoadScene r;
  for (const auto& p : d.reference_line) static_cast<void>(r.reference_line.push_back(p));
  r.road.lane_width = d.road.lane_width;
  r.road.left.offset = d.road.left.offset;
  r.road.right.offset = d.road.right.offset;
  for (const auto& b : d.road.left.table) static_cast<void>(r.road.left.table.push_back(b));
  for (const auto& b : d.road.right.table) static_cast<void>(r.road.right.table.push_back(b));
  r.road.target_lane_offset = d.road.target_lane_offset;
  r.road.speed_limit = d.road.speed_limit;
  r.ego = d.ego;
  for (const auto& o : d.static_obstacles) static_cast<void>(r.static_obstacles.push_back(o));
  for (const auto& o : d.dynamic_obstacles) {
    typename decltype(r.dynamic_obstacles)::value_type m;
    m.id = o.id;
    m.length = o.length;
    m.width = o.width;
    for (std::size_t k = 0; k < o.trajectory.size(); k += 2) static_cast<void>(m.trajectory.push_back(o.trajectory[k]));
    static_cast<void>(r.dynamic_obstacles.push_back(m));
  }
  // Arc length and right edge along the reference polyline.
  const std::size_t n = d.reference_line.size();
  double s_along = 0;
  int placed_parked = 0, placed_parallel = 0;
  for (std::size_t i = 0; i + 1 < n && (placed_parked < parked || placed_parallel < parallel); ++i) {
    const auto a = d.reference_line[i];
    const auto b = d.reference_line[i + 1];
    const double dx = b.x - a.x, dy = b.y - a.y, len = std::hypot(dx, dy);
    if (len > 1e-9 && i % 3 == 1) {
      const double ux = dx / len, uy = dy / len, heading = std::atan2(uy, ux);
      const double edge = d.road.right.at(s_along);
      if (placed_parked < parked) {
        itp::scene::StaticObstacle o;
        o.id = 1000 + placed_parked++;
        o.x = a.x - uy * (edge - 2.5);  // left normal (-uy, ux), l = edge - 2.5
        o.y = a.y + ux * (edge - 2.5);
        o.heading = heading;
        o.length = 4.5;
        o.width = 1.8;
        static_cast<void>(r.static_obstacles.push_back(o));
      } else if (placed_parallel < parallel) {
        typename decltype(r.dynamic_obstacles)::value_type m;
        m.id = 2000 + placed_parallel++;
        m.length = 4.5;
        m.width = 1.8;
        const double x0 = a.x - uy * (edge - 6.0), y0 = a.y + ux * (edge - 6.0);
        for (int k = 0; k < itp::RoadConfig::kMaxPredictionSamples; ++k) {
          itp::scene::TimedPose p;
          p.t = 0.2 * k;
          p.x = x0 + 10.0 * ux * p.t;
          p.y = y0 + 10.0 * uy * p.t;
          p.heading = heading;
          p.v = 10.0;
          static_cast<void>(m.trajectory.push_back(p));
        }
        static_cast<void>(r.dynamic_obstacles.push_back(m));
      }
    }
    s_along += len;
  }
  return r;
}

std::vector<RoadScene> make_road_scenes(int count, const hil::sim::GeneratorConfig& config, int parked,
                                        int parallel) {
  std::vector<RoadScene> out;
  for (const auto& s : make_scenes(count, config)) out.push_back(to_road(s, parked, parallel));
  return out;
}

void BM_FullCycle_Envelope_Road(benchmark::State& state) {
  static const auto scenes = make_road_scenes(kEnvelopeScenes, hil::sim::GeneratorConfig{}, 0, 0);
  run_suite(state, scenes);
}

void BM_FullCycle_Road_Busy_Plus16s_8d(benchmark::State& state) {
  hil::sim::GeneratorConfig busy;
  busy.min_static = busy.max_static = 10;
  busy.min_dynamic = busy.max_dynamic = 5;
  static const auto scenes = make_road_scenes(kBusyScenes, busy, 16, 8);
  run_suite(state, scenes);
}

}  // namespace

BENCHMARK(BM_FullCycle_Envelope)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_FullCycle_Busy_10s_5d)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_SteadyCycle_Envelope)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_FullCycle_Envelope_Road)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_FullCycle_Road_Busy_Plus16s_8d)->Unit(benchmark::kMillisecond)->MinTime(2.0);

BENCHMARK_MAIN();
