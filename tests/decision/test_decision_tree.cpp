#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <random>

#include "heap_guard.hpp"
#include "itp/decision/decision_tree.hpp"
#include "sl_scenes.hpp"

using namespace itp::decision;
using namespace decision_test;

namespace {

struct Built {
  std::unique_ptr<ConvexSpace> space = std::make_unique<ConvexSpace>();
  std::unique_ptr<DecisionSet> set = std::make_unique<DecisionSet>();
};

Built decide(const RoadSl& r, const std::vector<SlBox>& boxes, Scalar ego_l = 0) {
  Built b;
  REQUIRE(build_convex_space(r, boxes, params(ego_l), *b.space) == ConvexSpaceStatus::kOk);
  test_support::HeapGuard guard;
  enumerate_decisions(*b.space, GeometricWeights{}, *b.set);
  return b;
}

// Independent reference: every maximal path by plain recursion, its cost
// computed from the definition in docs/decision.md.
std::vector<Scalar> brute_force_costs(const ConvexSpace& sp, const GeometricWeights& w) {
  std::vector<Scalar> costs;
  const Scalar horizon = sp.s_end - sp.s_start;
  std::vector<int> path;
  std::function<void(int)> walk = [&](int zi) {
    path.push_back(zi);
    const Zone& z = sp.zones[static_cast<std::size_t>(zi)];
    if (z.successors == 0u) {
      Scalar cost = 0;
      Scalar length = 0;
      Scalar s_prev = sp.slice_of(sp.zones[static_cast<std::size_t>(path[0])]).s_begin;
      const Zone& z0 = sp.zones[static_cast<std::size_t>(path[0])];
      Scalar l_prev = 0.5 * (z0.l_min + z0.l_max);
      for (std::size_t k = 0; k < path.size(); ++k) {
        const Zone& a = sp.zones[static_cast<std::size_t>(path[k])];
        cost += w.area * a.area_cost + w.lane * a.lane_cost;
        if (k + 1 < path.size()) {
          const Zone& b = sp.zones[static_cast<std::size_t>(path[k + 1])];
          const Scalar lo = std::max(a.l_min, b.l_min);
          const Scalar hi = std::min(a.l_max, b.l_max);
          cost += w.link * sp.vehicle_width / (hi - lo);
          const Scalar l_cross = 0.5 * (lo + hi);
          length += std::hypot(sp.slice_of(b).s_begin - s_prev, l_cross - l_prev);
          s_prev = sp.slice_of(b).s_begin;
          l_prev = l_cross;
        } else {
          length += std::hypot(sp.slice_of(a).s_end - s_prev, 0.5 * (a.l_min + a.l_max) - l_prev);
          cost += w.move * length / horizon + w.blocked * (sp.s_end - sp.slice_of(a).s_end) / horizon;
        }
      }
      costs.push_back(cost);
    } else {
      for (int bit = 0; bit < 16; ++bit) {
        if ((z.successors & (1u << bit)) != 0u) {
          const Zone& c = sp.successor(z, bit);
          walk(static_cast<int>(&c - sp.zones.data()));
        }
      }
    }
    path.pop_back();
  };
  walk(sp.start_zone);
  std::sort(costs.begin(), costs.end());
  return costs;
}

}  // namespace

TEST_CASE("free road: one decision, in lane, reaching the horizon") {
  auto b = decide(road(-1.75, 5.25), {});
  REQUIRE(b.set->kept.size() == 1);
  const Decision& d = b.set->kept[0];
  CHECK(d.reaches_end);
  CHECK(d.lane_cost == doctest::Approx(0));
  CHECK(d.move_cost == doctest::Approx(1.0));  // a straight centre line over the horizon
}

TEST_CASE("one obstacle in a wide road: a left and a right decision, the roomier side wins") {
  // Road of three lanes [-5.25, 5.25]; the obstacle sits left of centre.
  const std::vector<SlBox> boxes{box(40, 45, -0.4, 1.4, 3)};
  auto b = decide(road(-5.25, 5.25), boxes);
  REQUIRE(b.set->kept.size() == 2);
  const Decision& best = b.set->kept[0];
  const Decision& other = b.set->kept[1];
  CHECK(side_of(*b.space, best, boxes[0]) == Side::kRight);  // 4.85 m on the right vs 3.85 m
  CHECK(side_of(*b.space, other, boxes[0]) == Side::kLeft);
  CHECK(best.reaches_end);
  CHECK(other.reaches_end);
  CHECK(best.geometric_cost < other.geometric_cost);

  // Mirror the obstacle: now the left side has more room and wins.
  const std::vector<SlBox> mirrored{box(40, 45, -1.4, 0.4, 3)};
  auto m = decide(road(-5.25, 5.25), mirrored);
  REQUIRE(m.set->kept.size() == 2);
  CHECK(side_of(*m.space, m.set->kept[0], mirrored[0]) == Side::kLeft);
}

TEST_CASE("an obstacle blocking every lane leaves no decision that reaches the horizon") {
  const std::vector<SlBox> boxes{box(40, 45, -3, 7, 1)};
  auto b = decide(road(-1.75, 5.25), boxes);
  REQUIRE(b.set->kept.size() == 1);
  CHECK_FALSE(b.set->kept[0].reaches_end);
  CHECK(b.set->kept[0].reach == doctest::Approx(40));
  CHECK(side_of(*b.space, b.set->kept[0], boxes[0]) == Side::kNotReached);
}

TEST_CASE("the target lane steers the choice between equally roomy sides") {
  // An obstacle on the lane divider; 4.5 m free on both sides.
  const std::vector<SlBox> boxes{box(40, 45, 1.0, 2.5, 5)};
  auto keep = decide(road(-3.5, 7.0, 0.0), boxes);
  REQUIRE(keep.set->kept.size() == 2);
  CHECK(side_of(*keep.space, keep.set->kept[0], boxes[0]) == Side::kRight);
  auto change = decide(road(-3.5, 7.0, 3.5), boxes);
  REQUIRE(change.set->kept.size() == 2);
  CHECK(side_of(*change.space, change.set->kept[0], boxes[0]) == Side::kLeft);
}

TEST_CASE("random scenes: branch and bound keeps exactly the K cheapest paths of a brute-force enumeration") {
  std::mt19937 rng(23);
  std::uniform_real_distribution<Scalar> u(0, 1);
  int checked = 0;
  int with_many = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<SlBox> boxes;
    const int n = 1 + static_cast<int>(rng() % 9);  // keeps brute force small
    for (int i = 0; i < n; ++i) {
      const Scalar s0 = 100 * u(rng);
      const Scalar l0 = -5 + 9 * u(rng);
      boxes.push_back(box(s0, s0 + 2 + 8 * u(rng), l0, l0 + 0.5 + 1.5 * u(rng), i));
    }
    Built b;
    if (build_convex_space(road(-5.25, 5.25), boxes, params(0), *b.space) != ConvexSpaceStatus::kOk) {
      continue;
    }
    {
      test_support::HeapGuard guard;
      enumerate_decisions(*b.space, GeometricWeights{}, *b.set);
    }
    if (b.set->truncated) {
      continue;
    }
    const auto ref = brute_force_costs(*b.space, GeometricWeights{});
    const std::size_t k = std::min<std::size_t>(ref.size(), itp::DefaultConfig::kKeptDecisions);
    REQUIRE(b.set->kept.size() == k);
    for (std::size_t i = 0; i < k; ++i) {
      CHECK(b.set->kept[i].geometric_cost == doctest::Approx(ref[i]).epsilon(1e-9));
    }
    // Every kept corridor is at least the vehicle width wide in every slice it uses.
    for (const Decision& d : b.set->kept) {
      for (std::size_t i = 0; i < d.zones.size(); ++i) {
        const Zone& z = b.space->zones[static_cast<std::size_t>(d.zones[i])];
        CHECK(z.width() >= 1.9);
        CHECK(z.slice == static_cast<std::int16_t>(i));
        if (i + 1 < d.zones.size()) {
          CHECK(ConvexSpace::overlap(z, b.space->zones[static_cast<std::size_t>(d.zones[i + 1])]) >= 1.9);
        }
      }
    }
    ++checked;
    with_many += ref.size() > itp::DefaultConfig::kKeptDecisions ? 1 : 0;
  }
  CHECK(checked > 300);
  CHECK(with_many > 5);  // the K limit was exercised
}

TEST_CASE("the node budget bounds the search and is reported") {
  // Many small obstacles scattered across a wide road: a huge tree.
  std::vector<SlBox> boxes;
  for (int i = 0; i < itp::DefaultConfig::kMaxObstacles; ++i) {
    const Scalar s0 = 5.0 + 6.0 * i;
    const Scalar l0 = (i % 3 == 0) ? -3.0 : (i % 3 == 1 ? 0.5 : 4.0);
    boxes.push_back(box(s0, s0 + 3, l0, l0 + 0.6, i));
  }
  Built b;
  itp::decision::RoadSl r = road(-12, 12);
  REQUIRE(build_convex_space(r, boxes, params(0), *b.space) == ConvexSpaceStatus::kOk);
  enumerate_decisions(*b.space, GeometricWeights{}, *b.set);
  CHECK(b.set->nodes_expanded <= itp::DefaultConfig::kMaxTreeNodes);
  CHECK(b.set->kept.size() == static_cast<std::size_t>(itp::DefaultConfig::kKeptDecisions));
  for (std::size_t i = 1; i < b.set->kept.size(); ++i) {
    CHECK(b.set->kept[i - 1].geometric_cost <= b.set->kept[i].geometric_cost);
  }
}
