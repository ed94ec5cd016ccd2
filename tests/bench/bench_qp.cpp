// bench_qp: cold / warm / hot solves of the planner-shaped QPs
// (tests/qp/planner_qps.hpp). A "sequence" is a replanning run: each QP
// differs from the previous one by a small move of the initial state and of
// the obstacle, as between two planning cycles. Warm solves start from the
// previous QP's working set (refactorising H); hot solves reuse everything.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <memory>
#include <vector>

#include "itp/qp/qp.hpp"
#include "default_qp_shapes.hpp"
#include "planner_qps.hpp"

using namespace itp::qp;

namespace {

constexpr int kSequence = 8;

template <class D>
struct Sequence {
  QpProblem<D> problems[kSequence];
  WorkingSet<D> solutions[kSequence];  // cold working set of each problem
  int cold_iterations[kSequence];
  QpWorkspace<D> ws;
  QpResult<D> result;
  QpSettings<typename D::Scalar> settings;
};

// Order 0,1,..,7,6,..,1,0,1,... so that neighbours are always close.
int ping_pong(long k) {
  const long period = 2 * (kSequence - 1);
  const long r = k % period;
  return static_cast<int>(r < kSequence ? r : period - r);
}

template <class D, class Build>
std::unique_ptr<Sequence<D>> make_sequence(Build build) {
  auto seq = std::make_unique<Sequence<D>>();
  for (int k = 0; k < kSequence; ++k) {
    if (!build(seq->problems[k], k)) std::abort();
    if (solve_cold(seq->problems[k], seq->ws, seq->settings, seq->result) != QpStatus::kOptimal) {
      std::fprintf(stderr, "bench instance %d not optimal\n", k);
      std::abort();
    }
    seq->solutions[k] = seq->result.working_set;
    seq->cold_iterations[k] = seq->result.iterations;
  }
  return seq;
}

template <class D>
void run_cold(benchmark::State& state, Sequence<D>& seq) {
  long k = 0;
  double iters = 0;
  for (auto _ : state) {
    const int i = ping_pong(k++);
    benchmark::DoNotOptimize(solve_cold(seq.problems[i], seq.ws, seq.settings, seq.result));
    iters += seq.result.iterations;
  }
  state.counters["iterations"] = iters / static_cast<double>(k);
}

template <class D>
void run_warm(benchmark::State& state, Sequence<D>& seq) {
  long k = 1;
  double iters = 0;
  for (auto _ : state) {
    const int prev = ping_pong(k - 1), i = ping_pong(k);
    ++k;
    benchmark::DoNotOptimize(
        solve_warm(seq.problems[i], seq.ws, seq.settings, seq.solutions[prev], seq.result));
    iters += seq.result.iterations;
  }
  state.counters["iterations"] = iters / static_cast<double>(k - 1);
}

template <class D>
void run_hot(benchmark::State& state, Sequence<D>& seq) {
  solve_cold(seq.problems[0], seq.ws, seq.settings, seq.result);
  long k = 1;
  double iters = 0;
  for (auto _ : state) {
    const int i = ping_pong(k++);
    benchmark::DoNotOptimize(solve_hot(seq.problems[i], seq.ws, seq.settings, seq.result));
    iters += seq.result.iterations;
  }
  state.counters["iterations"] = iters / static_cast<double>(k - 1);
}

// Replanning with the obstacle fixed in the road frame: the initial state and
// the obstacle's lateral edge (perception noise) change from cycle to cycle.
template <typename S>
bool path(QpProblem<PathQp<S>>& p, int k) {
  planner_qps::PathScenario sc;
  sc.init_l = 0.04 * k;
  sc.init_dl = 0.005 * k;
  sc.obstacle_left = 1.5 + 0.02 * k;
  return planner_qps::build_path_qp(p, sc);
}

// As above, and the obstacle also moves 0.5 m in s per cycle (one corridor
// sample): every active corridor row changes index -- a hard case for warm
// starts.
template <typename S>
bool path_shift(QpProblem<PathQp<S>>& p, int k) {
  planner_qps::PathScenario sc;
  sc.init_l = 0.04 * k;
  sc.init_dl = 0.005 * k;
  sc.obstacle_left = 1.5 + 0.02 * k;
  sc.obstacle_s0 = 40.0 - 0.5 * k;
  sc.obstacle_s1 = 55.0 - 0.5 * k;
  return planner_qps::build_path_qp(p, sc);
}

template <typename S>
bool speed(QpProblem<SpeedQp<S>>& p, int k) {
  planner_qps::SpeedScenario sc;
  sc.v0 = 15.0 - 0.1 * k;
  sc.lead_s0 = 30.0 - 0.6 * k;
  return planner_qps::build_speed_qp(p, sc);
}

template <typename S>
bool coarse(QpProblem<CoarseQp<S>>& p, int k) {
  planner_qps::CoarseScenario sc;
  sc.l_init = 0.03 * k;
  sc.obstacle_left = 2.45 + 0.02 * k;
  sc.wait_t = 5.0 + 0.05 * k;
  return planner_qps::build_coarse_qp(p, sc);
}

template <typename S>
Sequence<PathQp<S>>& path_seq() {
  static auto seq = make_sequence<PathQp<S>>(path<S>);
  return *seq;
}
Sequence<PathQp<double>>& path_shift_seq() {
  static auto seq = make_sequence<PathQp<double>>(path_shift<double>);
  return *seq;
}
template <typename S>
Sequence<SpeedQp<S>>& speed_seq() {
  static auto seq = make_sequence<SpeedQp<S>>(speed<S>);
  return *seq;
}
template <typename S>
Sequence<CoarseQp<S>>& coarse_seq() {
  static auto seq = make_sequence<CoarseQp<S>>(coarse<S>);
  return *seq;
}

void BM_PathCold(benchmark::State& s) { run_cold(s, path_seq<double>()); }
void BM_PathWarm(benchmark::State& s) { run_warm(s, path_seq<double>()); }
void BM_PathHot(benchmark::State& s) { run_hot(s, path_seq<double>()); }
void BM_PathShiftWarm(benchmark::State& s) { run_warm(s, path_shift_seq()); }
void BM_PathShiftHot(benchmark::State& s) { run_hot(s, path_shift_seq()); }
void BM_SpeedCold(benchmark::State& s) { run_cold(s, speed_seq<double>()); }
void BM_SpeedWarm(benchmark::State& s) { run_warm(s, speed_seq<double>()); }
void BM_SpeedHot(benchmark::State& s) { run_hot(s, speed_seq<double>()); }
void BM_CoarseCold(benchmark::State& s) { run_cold(s, coarse_seq<double>()); }
void BM_CoarseWarm(benchmark::State& s) { run_warm(s, coarse_seq<double>()); }
void BM_CoarseHot(benchmark::State& s) { run_hot(s, coarse_seq<double>()); }
void BM_PathColdFloat(benchmark::State& s) { run_cold(s, path_seq<float>()); }
void BM_PathWarmFloat(benchmark::State& s) { run_warm(s, path_seq<float>()); }

void BM_Sizes(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(state.iterations());
  state.counters["ws_path_B"] = sizeof(QpWorkspace<PathQp<double>>);
  state.counters["ws_speed_B"] = sizeof(QpWorkspace<SpeedQp<double>>);
  state.counters["ws_coarse_B"] = sizeof(QpWorkspace<CoarseQp<double>>);
  state.counters["problem_path_B"] = sizeof(QpProblem<PathQp<double>>);
  state.counters["result_path_B"] = sizeof(QpResult<PathQp<double>>);
}

}  // namespace

BENCHMARK(BM_PathCold)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PathWarm)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PathHot)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PathShiftWarm)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PathShiftHot)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SpeedCold)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SpeedWarm)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SpeedHot)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CoarseCold)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CoarseWarm)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CoarseHot)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PathColdFloat)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PathWarmFloat)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Sizes)->Iterations(1);

BENCHMARK_MAIN();
