#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "heap_guard.hpp"
#include "itp/speed/speed_optimizer.hpp"

using namespace itp::speed;
using itp::Scalar;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double sample_time(int k) { return 7.0 * k / itp::DefaultConfig::kSpeedSamples; }

// Open road at `limit` m/s: s_up is the furthest reachable s, ṡ_expect the limit.
SpeedBounds open_road(double limit) {
  SpeedBounds b;
  for (int k = 0; k <= itp::DefaultConfig::kSpeedSamples; ++k) {
    const auto u = static_cast<std::size_t>(k);
    b.s_lo[u] = 0;
    b.s_hi[u] = kInf;
    b.v_lo[u] = 0;
    b.v_hi[u] = limit;
    b.s_ref[u] = limit * sample_time(k);
    b.v_ref[u] = limit;
  }
  return b;
}

struct Fixture {
  std::unique_ptr<SpeedOptimizer::QpArena> arena = std::make_unique<SpeedOptimizer::QpArena>();
  std::unique_ptr<SpeedOptimizer> opt = std::make_unique<SpeedOptimizer>(*arena);
  SpeedResult r;
  void run(const SpeedInput& in, const SpeedBounds& b) {
    test_support::HeapGuard guard;
    opt->solve(in, b, SpeedWeights{}, r);
  }
};

// Dense check of the limits between samples (they are enforced at 0.1 s).
void check_limits(const SpeedResult& r, const SpeedInput& in, const SpeedBounds& b, double slack) {
  REQUIRE(itp::qp::is_usable(r.status));
  CHECK(r.eval(0, 0) == doctest::Approx(0));
  CHECK(r.eval(0, 1) == doctest::Approx(in.v0));
  for (int k = 1; k <= itp::DefaultConfig::kSpeedSamples; ++k) {
    const double t = sample_time(k);
    const auto u = static_cast<std::size_t>(k);
    CHECK(r.eval(t, 0) <= b.s_hi[u] + 1e-6);
    CHECK(r.eval(t, 0) >= b.s_lo[u] - 1e-6);
    CHECK(r.eval(t, 1) <= b.v_hi[u] + 1e-6);
    CHECK(r.eval(t, 1) >= b.v_lo[u] - 1e-6);
  }
  for (double t = 0; t <= 7.0; t += 0.02) {
    CHECK(r.eval(t, 2) <= in.a_max + slack);
    CHECK(r.eval(t, 2) >= in.a_min - slack);
  }
}

}  // namespace

TEST_CASE("open road: accelerates to the limit within the acceleration bound") {
  Fixture f;
  SpeedInput in;
  in.v0 = 5;
  const SpeedBounds b = open_road(15);
  f.run(in, b);
  check_limits(f.r, in, b, 0.05);
  CHECK(f.r.eval(7.0, 1) == doctest::Approx(15).epsilon(0.05));
}

TEST_CASE("cruise at the limit stays at the limit") {
  Fixture f;
  SpeedInput in;
  in.v0 = 12;
  const SpeedBounds b = open_road(12);
  f.run(in, b);
  check_limits(f.r, in, b, 0.02);
  for (double t = 0; t <= 7; t += 0.5) {
    CHECK(f.r.eval(t, 1) == doctest::Approx(12).epsilon(0.02));
  }
}

TEST_CASE("a stop line: stops before it, braking within the limit") {
  Fixture f;
  SpeedInput in;
  in.v0 = 10;
  SpeedBounds b = open_road(15);
  for (auto& s : b.s_hi) s = 30.0;  // v²/2|a| = 12.5 m at -4 m/s²: comfortably possible
  f.run(in, b);
  check_limits(f.r, in, b, 0.05);
  CHECK(f.r.eval(7.0, 0) <= 30.0 + 1e-6);
  CHECK(f.r.eval(7.0, 1) == doctest::Approx(0).scale(1).epsilon(0.05));
}

TEST_CASE("an impossible stop is reported as infeasible, not solved wrongly") {
  Fixture f;
  SpeedInput in;
  in.v0 = 20;
  SpeedBounds b = open_road(25);
  for (auto& s : b.s_hi) s = 10.0;  // needs 50 m to stop
  f.run(in, b);
  CHECK(f.r.status == itp::qp::QpStatus::kInfeasible);
}

TEST_CASE("follow: a leader's s bound keeps the gap and the speed settles on the leader's") {
  Fixture f;
  SpeedInput in;
  in.v0 = 12;
  SpeedBounds b = open_road(15);
  for (int k = 0; k <= itp::DefaultConfig::kSpeedSamples; ++k) {
    const auto u = static_cast<std::size_t>(k);
    b.s_hi[u] = 30.0 + 8.0 * sample_time(k) - 15.0;  // leader at 30 m, 8 m/s, 15 m gap
    b.v_hi[u] = std::min(15.0, k > 40 ? 8.0 : 15.0);
  }
  f.run(in, b);
  check_limits(f.r, in, b, 0.05);
  CHECK(f.r.eval(7.0, 1) == doctest::Approx(8).epsilon(0.1));
}
