// ReferenceLine construction: failure statuses, arc length, heading and the
// smoothed curvature against analytic curves.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "itp/geometry/reference_line.hpp"
#include "roads.hpp"

using itp::Scalar;
using itp::geometry::Point2;
using itp::geometry::ReferenceLine;
using itp::geometry::ReferenceLineStatus;
using itp::geometry::SmoothingSplineWorkspace;

namespace {
SmoothingSplineWorkspace g_ws;

ReferenceLineStatus try_build(const std::vector<Point2>& pts) {
  ReferenceLine line;
  const ReferenceLineStatus st = line.build(pts, g_ws);
  CHECK(line.valid() == (st == ReferenceLineStatus::kOk));
  return st;
}
}  // namespace

TEST_CASE("ReferenceLine rejects bad polylines with a named status") {
  const auto good = test_roads::straight({Scalar(0), Scalar(0)}, 0.0, 50.0, 5.0);
  CHECK(try_build(good) == ReferenceLineStatus::kOk);

  CHECK(try_build({}) == ReferenceLineStatus::kTooFewPoints);
  CHECK(try_build({good[0]}) == ReferenceLineStatus::kTooFewPoints);

  const auto too_many = test_roads::straight({Scalar(0), Scalar(0)}, 0.0,
                                             itp::DefaultConfig::kMaxReferencePoints, 1.0);
  REQUIRE(too_many.size() == itp::DefaultConfig::kMaxReferencePoints + 1);
  CHECK(try_build(too_many) == ReferenceLineStatus::kTooManyPoints);

  auto nan = good;
  nan[3].y = std::numeric_limits<Scalar>::quiet_NaN();
  CHECK(try_build(nan) == ReferenceLineStatus::kNonFinite);
  auto inf = good;
  inf[5].x = std::numeric_limits<Scalar>::infinity();
  CHECK(try_build(inf) == ReferenceLineStatus::kNonFinite);

  auto repeated = good;
  repeated.insert(repeated.begin() + 4, repeated[4]);
  CHECK(try_build(repeated) == ReferenceLineStatus::kRepeatedPoints);

  auto reversal = good;  // goes back on itself
  reversal.push_back({reversal.back().x - Scalar(3), reversal.back().y + Scalar(0.1)});
  CHECK(try_build(reversal) == ReferenceLineStatus::kSharpTurn);

  const auto too_short = test_roads::straight({Scalar(0), Scalar(0)}, 0.0, 0.6, 0.3);
  CHECK(try_build(too_short) == ReferenceLineStatus::kTooShort);
  // A short map ahead (the road ends) is still a line to plan a stop on.
  const auto short_map = test_roads::straight({Scalar(0), Scalar(0)}, 0.0, 6.0, 2.0);
  CHECK(try_build(short_map) == ReferenceLineStatus::kOk);

  // Two points are enough for a straight line.
  CHECK(try_build({{Scalar(0), Scalar(0)}, {Scalar(30), Scalar(40)}}) == ReferenceLineStatus::kOk);
}

TEST_CASE("Curvature of a sampled circle is 1/R within 2 %, dkappa/ds near 0") {
  for (double radius : {30.0, 50.0, 200.0}) {
    for (double spacing : {1.0, 5.0}) {
      const test_roads::Arc arc{radius};
      ReferenceLine line;
      REQUIRE(line.build(arc.sample(100.0, spacing), g_ws) == ReferenceLineStatus::kOk);
      CAPTURE(radius);
      CAPTURE(spacing);
      double worst = 0.0;
      double worst_dk = 0.0;
      for (double s = 0.0; s <= static_cast<double>(line.length()); s += 0.5) {
        const auto c = line.evaluate(static_cast<Scalar>(s));
        worst = std::max(worst, std::fabs(static_cast<double>(c.kappa) * radius - 1.0));
        worst_dk = std::max(worst_dk, std::fabs(static_cast<double>(c.dkappa)));
      }
      MESSAGE("R=" << radius << " spacing " << spacing << ": max |kappa R - 1| = " << worst
                   << ", max |dkappa/ds| = " << worst_dk);
      CHECK(worst < 0.02);
      CHECK(worst_dk < 0.02 / radius);
    }
  }
}

TEST_CASE("Heading and position along an arc match the circle") {
  const test_roads::Arc arc{50.0};
  ReferenceLine line;
  REQUIRE(line.build(arc.sample(100.0, 2.0), g_ws) == ReferenceLineStatus::kOk);
  for (double s = 0.0; s <= 100.0; s += 3.1) {
    const auto c = line.evaluate(static_cast<Scalar>(s));
    const Point2 exact = arc.at(s);
    CHECK(std::hypot(static_cast<double>(c.position.x - exact.x),
                     static_cast<double>(c.position.y - exact.y)) < 0.005);
    CHECK(static_cast<double>(c.heading) == doctest::Approx(s / 50.0).epsilon(1e-3));
  }
  // Straight extension outside the line keeps the end heading, zero curvature.
  const auto before = line.evaluate(Scalar(-4));
  CHECK(static_cast<double>(before.position.x) == doctest::Approx(-4.0).epsilon(1e-3));
  CHECK(before.kappa == Scalar(0));
}

TEST_CASE("The S-curve's curvature follows the analytic curvature and changes sign") {
  const test_roads::SineRoad road;
  ReferenceLine line;
  REQUIRE(line.build(road.sample(150.0, 2.5), g_ws) == ReferenceLineStatus::kOk);
  double worst = 0.0;
  for (double s = 2.0; s <= 148.0; s += 1.0) {
    const double x = road.x_at(s);
    const double d1 = road.dy(x);
    const double exact = road.ddy(x) / std::pow(1.0 + d1 * d1, 1.5);
    const auto c = line.evaluate(static_cast<Scalar>(s));
    worst = std::max(worst, std::fabs(static_cast<double>(c.kappa) - exact));
  }
  MESSAGE("S-curve max |kappa - exact| = " << worst << " 1/m (peak 0.0326)");
  CHECK(worst < 0.001);  // 3 % of the peak curvature
}

TEST_CASE("Smoothing keeps the curvature of a noisy sampled circle usable") {
  // 1 m spacing, +-2 cm deterministic noise on both coordinates. An
  // interpolating spline turns this into curvature errors of several 100 %
  // (docs/frenet.md); the smoothing spline keeps it within 10 %.
  const test_roads::Arc arc{50.0};
  auto pts = arc.sample(100.0, 1.0);
  std::uint32_t state = 12345u;
  const auto noise = [&state]() {
    state = state * 1664525u + 1013904223u;  // LCG: deterministic everywhere
    return static_cast<Scalar>((static_cast<double>(state >> 8) / 16777216.0 - 0.5) * 0.04);
  };
  for (auto& p : pts) {
    p.x += noise();
    p.y += noise();
  }
  ReferenceLine line;
  REQUIRE(line.build(pts, g_ws) == ReferenceLineStatus::kOk);
  double worst = 0.0;
  for (double s = 10.0; s <= 90.0; s += 0.25) {
    worst = std::max(worst, std::fabs(static_cast<double>(line.evaluate(static_cast<Scalar>(s)).kappa) * 50.0 - 1.0));
  }
  MESSAGE("noisy circle: max |kappa R - 1| = " << worst);
  CHECK(worst < 0.10);
}
