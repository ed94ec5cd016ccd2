// Google Benchmark of the reference line (docs/frenet.md): u(s) through
// evaluate(), the projection to_frenet(), to_cartesian(), the SL box and the
// planner's "project, then look up the reference heading" pattern. Lines:
// 0 = S-curve sampled every 2 m over 150 m (the simulator's spacing),
// 1 = arc R = 30 m sampled every 1 m over 120 m (121 points, near the
// capacity of 128). Queries are deterministic and spread over the whole line.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "../geometry/roads.hpp"
#include "itp/geometry/frenet.hpp"
#include "itp/geometry/reference_line.hpp"

namespace {

using itp::Scalar;
using itp::geometry::CurveSample;
using itp::geometry::FrenetPoint;
using itp::geometry::OrientedBox;
using itp::geometry::Point2;
using itp::geometry::ReferenceLine;

constexpr std::size_t kQueries = 4096;  // power of two: index wraps with a mask

struct Fixture {
  std::vector<Point2> polyline;
  ReferenceLine line;
  std::vector<Scalar> s;         // arc lengths in [0, length]
  std::vector<Point2> points;    // |l| <= 6 m around the line
  std::vector<FrenetPoint> sl;   // (s, l) with |l| <= 6 m
  std::vector<OrientedBox> boxes;
};

double uniform(std::uint32_t& state) {
  state = state * 1664525u + 1013904223u;
  return static_cast<double>(state >> 8) / 16777216.0;
}

const Fixture& fixture(int which) {
  static Fixture f[2];
  Fixture& x = f[which];
  if (!x.polyline.empty()) {
    return x;
  }
  x.polyline = which == 0 ? test_roads::SineRoad{}.sample(150.0, 2.0) : test_roads::Arc{30.0}.sample(120.0, 1.0);
  static itp::geometry::SmoothingSplineWorkspace ws;
  if (x.line.build(x.polyline, ws) != itp::geometry::ReferenceLineStatus::kOk) {
    std::abort();
  }
  std::uint32_t state = 777u;
  const double length = static_cast<double>(x.line.length());
  for (std::size_t i = 0; i < kQueries; ++i) {
    const double s = uniform(state) * length;
    const double l = (uniform(state) - 0.5) * 12.0;
    x.s.push_back(static_cast<Scalar>(s));
    x.sl.push_back({static_cast<Scalar>(s), static_cast<Scalar>(l)});
    const CurveSample c = x.line.evaluate(static_cast<Scalar>(s));
    const double h = static_cast<double>(c.heading);
    x.points.push_back({static_cast<Scalar>(static_cast<double>(c.position.x) - l * std::sin(h)),
                        static_cast<Scalar>(static_cast<double>(c.position.y) + l * std::cos(h))});
    x.boxes.push_back({x.points.back(), static_cast<Scalar>(h + (uniform(state) - 0.5) * 0.6), Scalar(4.5),
                       Scalar(1.8)});
  }
  return x;
}

void BM_Evaluate(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.line.evaluate(f.s[i++ & (kQueries - 1)]));
  }
}

void BM_ToFrenet(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.line.to_frenet(f.points[i++ & (kQueries - 1)]));
  }
}

// The planner's moving-box pattern: project, then the reference heading there.
void BM_ToFrenetThenEvaluate(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  for (auto _ : state) {
    const FrenetPoint c = f.line.to_frenet(f.points[i++ & (kQueries - 1)]);
    benchmark::DoNotOptimize(f.line.evaluate(c.s).heading);
  }
}

// The same with the foot-point overload: no second arc-length inversion.
void BM_ToFrenetWithFoot(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  for (auto _ : state) {
    CurveSample foot;
    const FrenetPoint c = f.line.to_frenet(f.points[i++ & (kQueries - 1)], foot);
    benchmark::DoNotOptimize(c);
    benchmark::DoNotOptimize(foot.heading);
  }
}

void BM_ToCartesian(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.line.to_cartesian(f.sl[i++ & (kQueries - 1)]));
  }
}

void BM_SlBoundingBoxCar(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(itp::geometry::sl_bounding_box(f.line, f.boxes[i++ & (kQueries - 1)], Scalar(0.3)));
  }
}

void BM_Build(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  static ReferenceLine line;
  static itp::geometry::SmoothingSplineWorkspace ws;
  for (auto _ : state) {
    benchmark::DoNotOptimize(line.build(f.polyline, ws));
  }
}

}  // namespace

BENCHMARK(BM_Evaluate)->Arg(0)->Arg(1);
BENCHMARK(BM_ToFrenet)->Arg(0)->Arg(1);
BENCHMARK(BM_ToFrenetThenEvaluate)->Arg(0)->Arg(1);
BENCHMARK(BM_ToFrenetWithFoot)->Arg(0)->Arg(1);
BENCHMARK(BM_ToCartesian)->Arg(0)->Arg(1);
BENCHMARK(BM_SlBoundingBoxCar)->Arg(0)->Arg(1);
BENCHMARK(BM_Build)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
