#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include "heap_guard.hpp"
#include "itp/decision/convex_space.hpp"
#include "sl_scenes.hpp"

using namespace itp::decision;
using namespace decision_test;

TEST_CASE("a free road is one zone spanning the horizon") {
  auto space = std::make_unique<ConvexSpace>();
  REQUIRE(build_convex_space(road(-1.75, 5.25), {}, params(), *space) == ConvexSpaceStatus::kOk);
  REQUIRE(space->slices.size() == 1);
  REQUIRE(space->zones.size() == 1);
  const Zone& z = space->zones[0];
  CHECK(space->slice_of(z).s_begin == doctest::Approx(0));
  CHECK(space->slice_of(z).s_end == doctest::Approx(100));
  CHECK(z.l_min == doctest::Approx(-1.75));
  CHECK(z.l_max == doctest::Approx(5.25));
  CHECK(z.area_cost == doctest::Approx(0));
  CHECK(z.lane_cost == doctest::Approx(0));  // covers the whole target lane
  CHECK(space->start_zone == 0);
}

TEST_CASE("an obstacle splits its slice into a left and a right zone") {
  const std::vector<SlBox> boxes{box(40, 45, -0.5, 1.5, 7)};
  auto space = std::make_unique<ConvexSpace>();
  REQUIRE(build_convex_space(road(-5.25, 5.25), boxes, params(), *space) == ConvexSpaceStatus::kOk);
  REQUIRE(space->slices.size() == 3);
  CHECK(space->slices[1].s_begin == doctest::Approx(40));
  CHECK(space->slices[1].s_end == doctest::Approx(45));
  REQUIRE(space->slices[1].zone_count == 2);
  const Zone& right = space->zones[static_cast<std::size_t>(space->slices[1].first_zone)];
  const Zone& left = space->zones[static_cast<std::size_t>(space->slices[1].first_zone + 1)];
  CHECK(right.l_min == doctest::Approx(-5.25));
  CHECK(right.l_max == doctest::Approx(-0.5));
  CHECK(right.left_box == 0);
  CHECK(left.l_min == doctest::Approx(1.5));
  CHECK(left.l_max == doctest::Approx(5.25));
  CHECK(left.right_box == 0);
  // Both link to the zones before and after (overlap >= vehicle width).
  CHECK(space->zones[0].successors == 0b11u);
  CHECK(right.successors == 0b1u);
  CHECK(left.successors == 0b1u);
}

TEST_CASE("an obstacle starting within the last 2 m of the horizon blocks only its own slice") {
  // Horizon [0, 100]; the box starts 1.2 m before the end. Merging that short
  // last slice into the one before stretched the box back to s = 0, so the
  // whole lane it stands in was blocked from the ego on.
  const std::vector<SlBox> boxes{box(98.8, 104, -1.75, 1.0, 2)};
  auto space = std::make_unique<ConvexSpace>();
  REQUIRE(build_convex_space(road(-1.75, 5.25), boxes, params(), *space) == ConvexSpaceStatus::kOk);
  REQUIRE(space->slices.size() == 2);
  CHECK(space->slices[0].s_end == doctest::Approx(98.8));
  REQUIRE(space->slices[0].zone_count == 1);
  const Zone& before = space->zones[static_cast<std::size_t>(space->slices[0].first_zone)];
  CHECK(before.l_min == doctest::Approx(-1.75));  // the ego's lane is free up to the box
  CHECK(before.l_max == doctest::Approx(5.25));
  CHECK(space->slices[1].s_begin == doctest::Approx(98.8));
  CHECK(space->slices[1].s_end == doctest::Approx(100));
}

TEST_CASE("gaps narrower than the vehicle are not zones") {
  const std::vector<SlBox> boxes{box(40, 45, -1.0, 5.25, 1)};  // leaves 0.75 m on the right
  auto space = std::make_unique<ConvexSpace>();
  REQUIRE(build_convex_space(road(-1.75, 5.25), boxes, params(), *space) == ConvexSpaceStatus::kOk);
  CHECK(space->slices[1].zone_count == 0);
  CHECK(space->zones[0].successors == 0u);
}

TEST_CASE("bad input is rejected with a status") {
  auto space = std::make_unique<ConvexSpace>();
  auto p = params();
  p.s_end = p.s_start;
  CHECK(build_convex_space(road(-1.75, 5.25), {}, p, *space) == ConvexSpaceStatus::kInvalidInput);
  const std::vector<SlBox> nan_box{box(10, std::nan(""), 0, 1, 1)};
  CHECK(build_convex_space(road(-1.75, 5.25), nan_box, params(), *space) == ConvexSpaceStatus::kInvalidInput);
  const std::vector<SlBox> inverted{box(10, 5, 0, 1, 1)};
  CHECK(build_convex_space(road(-1.75, 5.25), inverted, params(), *space) == ConvexSpaceStatus::kInvalidInput);
  std::vector<SlBox> too_many(itp::DefaultConfig::kMaxObstacles + 1, box(10, 12, 0, 1, 1));
  CHECK(build_convex_space(road(-1.75, 5.25), too_many, params(), *space) == ConvexSpaceStatus::kInvalidInput);
  const std::vector<SlBox> wall{box(-5, 5, -10, 10, 1)};  // covers the ego's slice entirely
  CHECK(build_convex_space(road(-1.75, 5.25), wall, params(), *space) == ConvexSpaceStatus::kNoStartZone);
}

TEST_CASE("random scenes: zones are inside the road, disjoint, wide enough (but a start gap holding the ego), and links are valid") {
  std::mt19937 rng(17);
  std::uniform_real_distribution<Scalar> u(0, 1);
  auto space = std::make_unique<ConvexSpace>();
  for (int trial = 0; trial < 300; ++trial) {
    const Scalar right = -1.75 - 3.5 * static_cast<Scalar>(rng() % 2);
    const Scalar left = 1.75 + 3.5 * static_cast<Scalar>(rng() % 3);
    std::vector<SlBox> boxes;
    const int n = static_cast<int>(rng() % (itp::DefaultConfig::kMaxObstacles + 1));
    for (int i = 0; i < n; ++i) {
      const Scalar s0 = -10 + 120 * u(rng);
      const Scalar l0 = right - 1 + (left - right + 2) * u(rng);
      boxes.push_back(box(s0, s0 + 2 + 10 * u(rng), l0, l0 + 0.5 + 2.5 * u(rng), i));
    }
    const auto r = road(right, left);
    ConvexSpaceStatus st;
    {
      test_support::HeapGuard guard;
      st = build_convex_space(r, boxes, params(0), *space);
    }
    if (st != ConvexSpaceStatus::kOk) {
      CHECK(st == ConvexSpaceStatus::kNoStartZone);
      continue;
    }
    REQUIRE(space->slices.size() <= static_cast<std::size_t>(itp::DefaultConfig::kMaxSlices));
    CHECK(space->slices[0].s_begin == doctest::Approx(0));
    CHECK(space->slices.back().s_end == doctest::Approx(100));
    for (std::size_t i = 0; i < space->slices.size(); ++i) {
      const Slice& sl = space->slices[i];
      if (i > 0) {
        CHECK(sl.s_begin == space->slices[i - 1].s_end);  // slices tile the horizon
      }
      for (int j = 0; j < sl.zone_count; ++j) {
        const Zone& z = space->zones[static_cast<std::size_t>(sl.first_zone + j)];
        CHECK(z.l_min >= right);
        CHECK(z.l_max <= left);
        // Wide enough; only a start zone may be narrower: the one gap of slice 0.
        const bool narrow_start = i == 0 && sl.zone_count == 1;
        CHECK((z.width() >= 1.9 || narrow_start));
        if (j > 0) {  // sorted and disjoint within the slice
          const Zone& prev = space->zones[static_cast<std::size_t>(sl.first_zone + j - 1)];
          CHECK(prev.l_max <= z.l_min);
        }
        for (const SlBox& b : boxes) {  // no zone overlaps an obstacle
          const bool s_overlap = b.s_max > sl.s_begin && b.s_min < sl.s_end;
          const bool l_overlap = b.l_max > z.l_min && b.l_min < z.l_max;
          CHECK_FALSE((s_overlap && l_overlap));
        }
        for (int bit = 0; bit < 16; ++bit) {
          if ((z.successors & (1u << bit)) != 0u) {
            REQUIRE(i + 1 < space->slices.size());
            // As wide as the vehicle, or all of a narrow start zone (the ego goes on straight).
            CHECK(ConvexSpace::overlap(z, space->successor(z, bit)) >= std::min(1.9, z.width()));
          }
        }
      }
    }
  }
}

TEST_CASE("road cuts: a narrowing far ahead does not narrow the ego's slice") {
  // Two lanes [-1.75, 5.25]; the right edge moves in by 3.5 m between s = 60
  // and s = 90 (the ego's lane ends). One slice over the whole horizon took
  // the narrowest road, [1.75, 5.25], which excludes the ego at l = 0.
  RoadSl r = road(-1.75, 5.25, 3.5);
  r.right = LateralProfile{};
  REQUIRE(r.right.add(0, -1.75));
  REQUIRE(r.right.add(60, -1.75));
  REQUIRE(r.right.add(90, 1.75));
  auto space = std::make_unique<ConvexSpace>();
  SUBCASE("without road cuts (the old slicing): no zone holds the ego") {
    REQUIRE(build_convex_space(r, {}, params(), *space) == ConvexSpaceStatus::kOk);
    REQUIRE(space->slices.size() == 1);
    CHECK(space->zones[0].l_min == doctest::Approx(1.75));
  }
  SUBCASE("with road cuts: the slice before the narrowing keeps the whole road") {
    select_road_cuts(r, 0, 100, 0.1, 4.0);
    REQUIRE_FALSE(r.cuts.empty());
    CHECK(r.cuts.size() <= static_cast<std::size_t>(itp::DefaultConfig::kMaxRoadCuts));
    CHECK(r.cuts[0] == doctest::Approx(60));  // the first cut where the edge starts to move
    REQUIRE(build_convex_space(r, {}, params(), *space) == ConvexSpaceStatus::kOk);
    REQUIRE(space->slices.size() == r.cuts.size() + 1);
    const Zone& first = space->zones[static_cast<std::size_t>(space->start_zone)];
    CHECK(first.slice == 0);
    CHECK(first.l_min == doctest::Approx(-1.75));
    CHECK(space->slice_of(first).s_end == doctest::Approx(60));
    // Every slice is a rectangle inside the road over its whole length, and
    // the slices along the taper lose less than the taper's 3.5 m.
    for (const Zone& z : space->zones) {
      const Slice& sl = space->slice_of(z);
      CHECK(z.l_min >= r.right.max_over(sl.s_begin, sl.s_end) - 1e-9);
      CHECK(z.l_max <= r.left.min_over(sl.s_begin, sl.s_end) + 1e-9);
      if (sl.s_begin >= 60 - 1e-9 && sl.s_end <= 90 + 1e-9) {
        CHECK(r.right.max_over(sl.s_begin, sl.s_end) - r.right.min_over(sl.s_begin, sl.s_end) < 1.0);
      }
    }
    // The ego's zone links through to the end (the left lane stays open).
    int slice = 0;
    int zone = space->start_zone;
    while (space->zones[static_cast<std::size_t>(zone)].successors != 0u) {
      const Zone& z = space->zones[static_cast<std::size_t>(zone)];
      int bit = 0;
      while (((z.successors >> bit) & 1u) == 0u) ++bit;
      zone = space->slices[static_cast<std::size_t>(slice + 1)].first_zone + bit;
      ++slice;
    }
    CHECK(slice == static_cast<int>(space->slices.size()) - 1);
  }
}

TEST_CASE("road cuts: none for constant or barely varying edges, never more than the budget") {
  RoadSl r = road(-1.75, 5.25);
  select_road_cuts(r, 0, 100, 0.1, 4.0);
  CHECK(r.cuts.empty());
  // A noisy edge (+-3 cm, as a recorded map) loses less than the tolerance.
  r.left = LateralProfile{};
  for (int k = 0; k < 32; ++k) {
    REQUIRE(r.left.add(4.0 * k, 5.25 + ((k % 2) != 0 ? 0.03 : -0.02)));
  }
  select_road_cuts(r, 0, 100, 0.1, 4.0);
  CHECK(r.cuts.empty());
  // A zig-zag of 1 m every 4 m: the budget, cuts ascending inside the horizon
  // and at least 4 m apart.
  r.left = LateralProfile{};
  for (int k = 0; k < 32; ++k) {
    REQUIRE(r.left.add(4.0 * k, 5.25 + ((k % 2) != 0 ? 1.0 : 0.0)));
  }
  select_road_cuts(r, 0, 100, 0.1, 4.0);
  CHECK(r.cuts.size() == static_cast<std::size_t>(itp::DefaultConfig::kMaxRoadCuts));
  Scalar last = 0;
  for (const Scalar c : r.cuts) {
    CHECK(c > last + 4.0 - 1e-9);
    CHECK(c < 100 - 4.0 + 1e-9);
    last = c;
  }
}

TEST_CASE("a box ending just ahead of the ego ends there, not at the next cut") {
  // A car behind in the left lane whose sweep ends 1.7 m ahead of the ego. Cuts
  // closer than 2 m merge, and dropping that one stretched the box over the
  // whole next slice (to the next obstacle 34 m ahead): the ego's corridor was
  // its lane's right part for 34 m although it stood beside it.
  const std::vector<SlBox> boxes{box(-12, 1.7, 1.2, 4.3, 1), box(34, 44, 4.9, 7.7, 2)};
  auto space = std::make_unique<ConvexSpace>();
  REQUIRE(build_convex_space(road(-1.4, 7.7), boxes, params(0.3), *space) == ConvexSpaceStatus::kOk);
  REQUIRE(space->slices.size() >= 3);
  CHECK(space->slices[0].s_end == doctest::Approx(1.7));
  CHECK(space->slices[1].s_begin == doctest::Approx(1.7));
  CHECK(space->slices[1].s_end == doctest::Approx(34));
  REQUIRE(space->slices[1].zone_count == 1);
  const Zone& free = space->zones[static_cast<std::size_t>(space->slices[1].first_zone)];
  CHECK(free.l_min == doctest::Approx(-1.4));
  CHECK(free.l_max == doctest::Approx(7.7));
}

namespace {

// Zones lost to capacity would leave Σ zone_count (counted per slice as each
// gap is found) above zones.size() (what was stored).
std::size_t zones_found(const ConvexSpace& space) {
  std::size_t n = 0;
  for (const Slice& sl : space.slices) n += static_cast<std::size_t>(sl.zone_count);
  return n;
}

}  // namespace

TEST_CASE("zone capacity: the worst case of N nested boxes with every road cut inside holds exactly kMaxZones") {
  // 15 boxes nested in s (2 m apart, the shortest slice kept), narrow and
  // spread across a 40 m road so that every gap in every slice is a zone, and
  // the 8 road cuts inside the innermost box: each box overlaps one slice per
  // cut inside it plus one, and each slice has (its boxes + 1) zones.
  using Cfg = itp::DefaultConfig;
  constexpr int kN = Cfg::kMaxDecisionObstacles;
  constexpr int kR = Cfg::kMaxRoadCuts;
  RoadSl r = road(-20, 20);
  for (int c = 0; c < kR; ++c) {
    REQUIRE(r.cuts.push_back(static_cast<Scalar>(2 * kN + 3 + 4 * c)));
  }
  std::vector<SlBox> boxes;
  for (int k = 0; k < kN; ++k) {
    const Scalar l0 = -17.5 + 2.4 * static_cast<Scalar>(k);
    boxes.push_back(box(2 + 2 * static_cast<Scalar>(k), 98 - 2 * static_cast<Scalar>(k), l0, l0 + 0.4, k));
  }
  REQUIRE(r.cuts.back() < boxes.back().s_max);
  auto space = std::make_unique<ConvexSpace>();
  REQUIRE(build_convex_space(r, boxes, params(), *space) == ConvexSpaceStatus::kOk);
  CHECK(space->slices.size() == static_cast<std::size_t>(Cfg::kMaxSlices));
  // Counted independently of the formula in config.hpp: box k contains the
  // ends of boxes k+1..N-1 and every road cut.
  std::size_t expected = space->slices.size();
  for (int k = 0; k < kN; ++k) expected += static_cast<std::size_t>(2 * (kN - 1 - k) + kR + 1);
  CHECK(zones_found(*space) == expected);
  CHECK(expected == static_cast<std::size_t>(Cfg::kMaxZones));  // the bound is tight
  CHECK(space->zones.size() == expected);                        // and nothing was lost
}

TEST_CASE("zone capacity: random wide-road scenes never lose a zone") {
  using Cfg = itp::DefaultConfig;
  std::mt19937 rng(20261126);
  std::uniform_real_distribution<Scalar> u(0, 1);
  auto space = std::make_unique<ConvexSpace>();
  std::size_t most = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    RoadSl r = road(-20, 20);
    const int cuts = static_cast<int>(rng() % (Cfg::kMaxRoadCuts + 1));
    Scalar c = 0;
    for (int i = 0; i < cuts; ++i) {
      c += 2 + 10 * u(rng);
      if (c < 100) REQUIRE(r.cuts.push_back(c));
    }
    std::vector<SlBox> boxes;
    const int n = static_cast<int>(rng() % (Cfg::kMaxDecisionObstacles + 1));
    for (int i = 0; i < n; ++i) {
      const Scalar s0 = -10 + 110 * u(rng);
      const Scalar l0 = -20 + 40 * u(rng);
      boxes.push_back(box(s0, s0 + 1 + 80 * u(rng), l0, l0 + 0.2 + 1.0 * u(rng), i));
    }
    if (build_convex_space(r, boxes, params(), *space) != ConvexSpaceStatus::kOk) continue;
    REQUIRE(zones_found(*space) == space->zones.size());
    most = std::max(most, space->zones.size());
  }
  MESSAGE("most zones in a random scene: " << most << " of " << Cfg::kMaxZones);
  CHECK(most > 0);
}

TEST_CASE("lateral_move_to_free_gap: the least move to a clear position, against a brute-force scan") {
  // Reference: centres every millimetre across the road, each tested for
  // clearance from the edges and every box overlapping [sa, sb] directly.
  std::mt19937 rng(23);
  std::uniform_real_distribution<Scalar> u(0, 1);
  for (int trial = 0; trial < 300; ++trial) {
    const Scalar right = -1.75 - 3.5 * static_cast<Scalar>(rng() % 2);
    const Scalar left = 1.75 + 3.5 * static_cast<Scalar>(rng() % 3);
    std::vector<SlBox> boxes;
    const int n = static_cast<int>(rng() % 5);
    for (int i = 0; i < n; ++i) {
      const Scalar s0 = 20 * u(rng);
      const Scalar l0 = right + (left - right) * u(rng);
      boxes.push_back(box(s0, s0 + 2 + 10 * u(rng), l0, l0 + 0.3 + 2.5 * u(rng), i + 1));
    }
    const Scalar sa = 5 + 5 * u(rng), sb = sa + 5 * u(rng);
    const Scalar l = right + (left - right) * u(rng);
    const Scalar width = 1.9;
    Scalar expected = std::numeric_limits<Scalar>::infinity();
    for (Scalar c = right + width / 2; c <= left - width / 2 + 1e-12; c += 0.001) {
      bool clear = true;
      for (const SlBox& b : boxes) {
        const bool in_s = b.s_max > sa && b.s_min < sb;
        clear = clear && !(in_s && c + width / 2 > b.l_min && c - width / 2 < b.l_max);
      }
      if (clear) expected = std::min(expected, std::fabs(c - l));
    }
    const Scalar got = lateral_move_to_free_gap<itp::DefaultConfig>(road(right, left), boxes, sa, sb, l, width);
    if (std::isinf(expected)) {
      CHECK(std::isinf(got));
    } else {
      CHECK(std::fabs(got - expected) <= 0.0011);  // the scan's step
    }
  }
}

TEST_CASE("no gap as wide as the vehicle at the start: the gap holding the ego is the start zone, linked where it goes on") {
  // The ego half way past a parked car (right of it) with an oncoming car's
  // sweep on its left: 1.24 m between them. The gap is the start zone (before,
  // kNoStartZone: no decision, and the ego stood in the oncoming lane).
  auto space = std::make_unique<ConvexSpace>();
  const std::vector<SlBox> boxes{box(-5, 6, -1.75, 0.55, 1), box(-5, 60, 1.79, 5.25, 2)};
  REQUIRE(build_convex_space(road(-1.75, 5.25), boxes, params(1.2), *space) == ConvexSpaceStatus::kOk);
  const Zone& start = space->zones[static_cast<std::size_t>(space->start_zone)];
  CHECK(start.l_min == doctest::Approx(0.55));
  CHECK(start.l_max == doctest::Approx(1.79));
  CHECK(start.right_box == 0);
  CHECK(start.left_box == 1);
  // Past the parked car the free [-1.75, 1.79] holds all of it: linked.
  REQUIRE(space->slices.size() >= 2);
  REQUIRE(start.successors != 0u);
  const Zone& next = space->successor(start, 0);
  CHECK(next.l_min == doctest::Approx(-1.75));
  CHECK(next.l_max == doctest::Approx(1.79));
  // An ego whose centre lies in the sweep's margin: the nearest gap is its start zone all the same.
  REQUIRE(build_convex_space(road(-1.75, 5.25), boxes, params(2.1), *space) == ConvexSpaceStatus::kOk);
  CHECK(space->zones[static_cast<std::size_t>(space->start_zone)].l_min == doctest::Approx(0.55));
  // No free gap at all across the road: no start zone.
  const std::vector<SlBox> wall{box(-5, 6, -1.75, 5.25, 1)};
  CHECK(build_convex_space(road(-1.75, 5.25), wall, params(0.0), *space) == ConvexSpaceStatus::kNoStartZone);
}
