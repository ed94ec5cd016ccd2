// Frenet accuracy against analytic roads: the projection itself (s, l
// against the exact curve) and the Cartesian -> Frenet -> Cartesian round trip.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "heap_guard.hpp"
#include "itp/geometry/reference_line.hpp"
#include "roads.hpp"

using itp::Scalar;
using itp::geometry::FrenetPoint;
using itp::geometry::Point2;
using itp::geometry::ReferenceLine;
using itp::geometry::ReferenceLineStatus;
using itp::geometry::SmoothingSplineWorkspace;
using test_roads::scalar_tol;

namespace {

struct Errors {
  double s = 0.0;           // max |s - s_exact| [m]
  double l = 0.0;           // max |l - l_exact| [m]
  double round_trip = 0.0;  // max |p - to_cartesian(to_frenet(p))| [m]
};

ReferenceLine build_line(const std::vector<Point2>& pts) {
  static SmoothingSplineWorkspace ws;  // test-only: keeps the stack small
  ReferenceLine line;
  const ReferenceLineStatus st = line.build(pts, ws);
  REQUIRE(st == ReferenceLineStatus::kOk);
  return line;
}

template <typename ExactFrenet, typename ExactXY>
Errors measure(const ReferenceLine& line, double s_from, double s_to, ExactXY to_xy,
               ExactFrenet to_sl) {
  Errors e;
  // Grid over [s_from, s_to] and |l| <= 6 m.
  for (double s = s_from; s <= s_to; s += 0.37) {
    for (double l = -6.0; l <= 6.0; l += 0.5) {
      double x = 0.0;
      double y = 0.0;
      to_xy(s, l, x, y);
      const Point2 p{static_cast<Scalar>(x), static_cast<Scalar>(y)};
      const FrenetPoint f = line.to_frenet(p);
      double s_exact = 0.0;
      double l_exact = 0.0;
      to_sl(static_cast<double>(p.x), static_cast<double>(p.y), s, s_exact, l_exact);
      e.s = std::max(e.s, std::fabs(static_cast<double>(f.s) - s_exact));
      e.l = std::max(e.l, std::fabs(static_cast<double>(f.l) - l_exact));
      const Point2 q = line.to_cartesian(f);
      e.round_trip = std::max(e.round_trip, std::hypot(static_cast<double>(q.x - p.x),
                                                       static_cast<double>(q.y - p.y)));
    }
  }
  return e;
}

void report(const char* name, double spacing, const Errors& e) {
  std::printf("%-18s spacing %.1f m: |ds| %.2e m, |dl| %.2e m, round trip %.2e m\n", name,
              spacing, e.s, e.l, e.round_trip);
}

}  // namespace

TEST_CASE("Frenet on a straight road is exact (projection and round trip)") {
  const double theta = 0.52;  // [rad] not axis-aligned on purpose
  const Point2 origin{Scalar(12), Scalar(-7)};
  for (double spacing : {1.0, 2.5, 5.0}) {
    const double length = 120.0;
    const ReferenceLine line = build_line(test_roads::straight(origin, theta, length, spacing));
    CHECK(std::fabs(static_cast<double>(line.length()) - length) < scalar_tol(1e-9, 1e-3));
    const Errors e = measure(
        line, 0.0, length,
        [&](double s, double l, double& x, double& y) {
          x = static_cast<double>(origin.x) + s * std::cos(theta) - l * std::sin(theta);
          y = static_cast<double>(origin.y) + s * std::sin(theta) + l * std::cos(theta);
        },
        [&](double x, double y, double, double& s, double& l) {
          const double dx = x - static_cast<double>(origin.x);
          const double dy = y - static_cast<double>(origin.y);
          s = dx * std::cos(theta) + dy * std::sin(theta);
          l = -dx * std::sin(theta) + dy * std::cos(theta);
        });
    report("straight", spacing, e);
    CHECK(e.s < scalar_tol(1e-8, 2e-3));
    CHECK(e.l < scalar_tol(1e-8, 2e-3));
    CHECK(e.round_trip < scalar_tol(1e-8, 2e-3));
  }
}

TEST_CASE("Frenet on arcs of radius 30, 50 and 200 m matches the exact polar coordinates") {
  for (double radius : {30.0, 50.0, 200.0}) {
    for (double spacing : {1.0, 2.5, 5.0}) {
      const test_roads::Arc arc{radius};
      const double length = 100.0;
      const ReferenceLine line = build_line(arc.sample(length, spacing));
      CAPTURE(radius);
      CAPTURE(spacing);
      CHECK(std::fabs(static_cast<double>(line.length()) - length) < 5e-3);
      const Errors e = measure(
          line, 0.0, length,
          [&](double s, double l, double& x, double& y) { arc.frenet_to_xy(s, l, x, y); },
          [&](double x, double y, double hint, double& s, double& l) { arc.xy_to_frenet(x, y, s, l, hint); });
      char name[32];
      std::snprintf(name, sizeof name, "arc R=%.0f", radius);
      report(name, spacing, e);
      CHECK(e.s < 0.01);
      CHECK(e.l < 0.01);
      CHECK(e.round_trip < 0.01);
    }
  }
}

TEST_CASE("Frenet on an S-curve (minimum radius 30.6 m) matches the exact curve") {
  // The road starts and ends at inflection points, where dkappa/ds is
  // largest: the mirrored end extension assumes dkappa/ds = 0 there
  // (docs/frenet.md), so the first and last 10 m get a looser bound on s.
  const test_roads::SineRoad road;
  const double length = 150.0;  // beyond one wavelength: both turning directions
  for (double spacing : {1.25, 2.5, 5.0}) {
    const ReferenceLine line = build_line(road.sample(length, spacing));
    CAPTURE(spacing);
    const auto to_xy = [&](double s, double l, double& x, double& y) {
      const double xc = road.x_at(s);
      const double n = std::sqrt(1.0 + road.dy(xc) * road.dy(xc));
      x = xc - l * road.dy(xc) / n;
      y = road.y(xc) + l / n;
    };
    const auto to_sl = [&](double x, double y, double s_hint, double& s, double& l) {
      road.xy_to_frenet(x, y, road.x_at(s_hint), s, l);
    };
    const Errors inner = measure(line, 10.0, length - 10.0, to_xy, to_sl);
    const Errors front = measure(line, 0.0, 10.0, to_xy, to_sl);
    const Errors back = measure(line, length - 10.0, length, to_xy, to_sl);
    report("S-curve interior", spacing, inner);
    report("S-curve first 10 m", spacing, front);
    report("S-curve last 10 m", spacing, back);
    CHECK(inner.s < 0.01);
    CHECK(inner.l < 0.01);
    CHECK(inner.round_trip < 0.01);
    for (const Errors& e : {front, back}) {
      CHECK(e.s < 0.06);
      CHECK(e.l < 0.01);
      CHECK(e.round_trip < 0.01);
    }
  }
}

TEST_CASE("Points beyond the ends use the straight extension consistently") {
  const test_roads::Arc arc{50.0};
  const ReferenceLine line = build_line(arc.sample(60.0, 2.0));
  const Point2 before{Scalar(-5), Scalar(1)};  // behind the start (heading +x)
  const FrenetPoint f = line.to_frenet(before);
  CHECK(static_cast<double>(f.s) == doctest::Approx(-5.0).epsilon(1e-3));
  CHECK(static_cast<double>(f.l) == doctest::Approx(1.0).epsilon(1e-3));
  const Point2 back = line.to_cartesian(f);
  CHECK(std::hypot(static_cast<double>(back.x - before.x), static_cast<double>(back.y - before.y)) <
        scalar_tol(1e-9, 1e-4));
  // Beyond the end: 7 m further along the end tangent, 2 m to the right.
  const auto end = line.evaluate(line.length());
  const Point2 beyond{end.position.x + Scalar(7) * std::cos(end.heading) + Scalar(2) * std::sin(end.heading),
                      end.position.y + Scalar(7) * std::sin(end.heading) - Scalar(2) * std::cos(end.heading)};
  const FrenetPoint g = line.to_frenet(beyond);
  CHECK(static_cast<double>(g.s - line.length()) == doctest::Approx(7.0).epsilon(1e-4));
  CHECK(static_cast<double>(g.l) == doctest::Approx(-2.0).epsilon(1e-4));
}

TEST_CASE("Construction and projection do not allocate") {
  const test_roads::SineRoad road;
  const std::vector<Point2> pts = road.sample(120.0, 1.0);  // allocation outside the guard
  static SmoothingSplineWorkspace ws;
  static ReferenceLine line;
  test_support::HeapGuard guard;
  REQUIRE(line.build(pts, ws) == ReferenceLineStatus::kOk);
  const FrenetPoint f = line.to_frenet({Scalar(40), Scalar(3)});
  const Point2 p = line.to_cartesian(f);
  const auto c = line.evaluate(Scalar(55));
  CHECK(std::isfinite(p.x + c.kappa));
}
