#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "heap_guard.hpp"
#include "itp/speed/st_graph.hpp"

using namespace itp::speed;
using itp::Scalar;
using itp::decision::SlBox;

namespace {

double t_of(int k) { return 7.0 * k / itp::DefaultConfig::kSpeedSamples; }

itp::path::PathResult straight_path() {
  itp::path::PathResult p;
  p.status = itp::qp::QpStatus::kOptimal;
  p.s0 = 0;
  p.h = 5;
  return p;  // all knots zero: l(s) = 0
}

// A box moving with constant velocity (ds/dt, dl/dt) in SL.
DynamicTrack mover(int id, double s, double l, double vs, double vl, double len, double wid) {
  DynamicTrack tr;
  tr.id = id;
  for (int k = 0; k < itp::DefaultConfig::kStSamples; ++k) {
    const double t = t_of(k);
    SlBox b;
    b.s_min = s + vs * t - len / 2;
    b.s_max = s + vs * t + len / 2;
    b.l_min = l + vl * t - wid / 2;
    b.l_max = l + vl * t + wid / 2;
    b.obstacle_id = id;
    b.dynamic = true;
    tr.box[static_cast<std::size_t>(k)] = b;
    tr.present[static_cast<std::size_t>(k)] = true;
  }
  return tr;
}

struct Run {
  std::unique_ptr<StGraph> graph = std::make_unique<StGraph>();
  std::unique_ptr<SpeedOptimizer::QpArena> arena = std::make_unique<SpeedOptimizer::QpArena>();
  std::unique_ptr<SpeedOptimizer> opt = std::make_unique<SpeedOptimizer>(*arena);
  SpeedBounds bounds;
  SpeedResult speed;
  StParams params;

  void go(const std::vector<DynamicTrack>& tracks, double v0) {
    params.v0 = v0;
    params.limits.speed_limit = 15;
    params.limits.a_min = -4;  // the speed QP's default braking bound (SpeedInput)
    params.limits.a_max = 2;
    params.limits.lat_acc_max = 2.5;
    std::array<Scalar, itp::DefaultConfig::kStSamples> s_guess{};
    std::array<Scalar, itp::DefaultConfig::kStSamples> v_guess{};
    reference_profile(params, 7.0, s_guess, v_guess);
    const auto path = straight_path();
    test_support::HeapGuard guard;
    graph->build(path, tracks, params, s_guess, v_guess, bounds);
    SpeedInput in;
    in.v0 = v0;
    opt->solve(in, bounds, SpeedWeights{}, speed);
  }
};

}  // namespace

TEST_CASE("a slow leader in the lane is followed at a time gap, never closer") {
  Run r;
  const auto leader = mover(1, 40, 0, 8, 0, 4.5, 1.8);
  r.go({leader}, 12);
  REQUIRE(r.graph->decisions().size() == 1);
  CHECK(r.graph->decisions()[0].decision == Longitudinal::kFollow);
  REQUIRE(itp::qp::is_usable(r.speed.status));
  for (int k = 0; k < itp::DefaultConfig::kStSamples; ++k) {
    const double t = t_of(k);
    const double leader_rear = 40 + 8 * t - 2.25;
    const double ego_front = r.speed.eval(t, 0) + r.params.front;
    CHECK(leader_rear - ego_front >= r.params.follow_distance - 1e-6);
  }
  // Closing speed only as large as braking can still absorb over the remaining gap.
  for (int k = 0; k < itp::DefaultConfig::kStSamples; ++k) {
    const double t = t_of(k);
    const double v = r.speed.eval(t, 1);
    const double gap = (40 + 8 * t - 2.25) - (r.speed.eval(t, 0) + r.params.front) - r.params.follow_distance - 1.2 * 8;
    CHECK(v <= 8 + std::sqrt(2 * 4.0 * std::max(gap, 0.0)) + 0.5);
  }
  CHECK(r.speed.eval(7, 1) < 12.0);
}

TEST_CASE("a crossing pedestrian the ego cannot beat is yielded to") {
  Run r;
  // Crosses l from -4 to +4 at 1.2 m/s at s = 30: in the swept path for about 2.6 s.
  const auto ped = mover(2, 30, -4, 0, 1.2, 1.0, 1.0);
  r.go({ped}, 10);
  REQUIRE(r.graph->decisions().size() == 1);
  const StDecision& d = r.graph->decisions()[0];
  CHECK(d.decision == Longitudinal::kYield);
  REQUIRE(itp::qp::is_usable(r.speed.status));
  for (int k = d.k1; k <= d.k2; ++k) {
    const double t = t_of(k);
    // The ego's front stays behind the pedestrian's box while it is in the path.
    CHECK(r.speed.eval(t, 0) + r.params.front <= 30 - 0.5 + 1e-6);
  }
}

TEST_CASE("cars in the adjacent lane and behind the ego are ignored") {
  Run r;
  const auto adjacent = mover(3, 20, 3.5, 10, 0, 4.5, 1.8);
  const auto behind = mover(4, -20, 0, 14, 0, 4.5, 1.8);
  r.go({adjacent, behind}, 10);
  REQUIRE(r.graph->decisions().size() == 2);
  CHECK(r.graph->decisions()[0].decision == Longitudinal::kIgnore);
  CHECK(r.graph->decisions()[1].decision == Longitudinal::kIgnore);
  REQUIRE(itp::qp::is_usable(r.speed.status));
  CHECK(r.speed.eval(7, 1) == doctest::Approx(15).epsilon(0.05));
}

TEST_CASE("a pedestrian crossing far ahead after the ego has passed is overtaken") {
  Run r;
  // Enters the lane at about t = 5 s at s = 25; the ego at 14 m/s is long past.
  const auto ped = mover(5, 25, -7, 0, 1.2, 1.0, 1.0);
  r.go({ped}, 14);
  REQUIRE(r.graph->decisions().size() == 1);
  CHECK(r.graph->decisions()[0].decision == Longitudinal::kOvertake);
  REQUIRE(itp::qp::is_usable(r.speed.status));
}
