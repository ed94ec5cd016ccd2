// to_frenet(p, foot): the projection plus the reference curve at the foot
// point, against evaluate(s) and against analytic circles; and the pruned
// coarse search against a brute-force nearest point on a road that comes
// back close to itself.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "heap_guard.hpp"
#include "itp/geometry/angle.hpp"
#include "itp/geometry/reference_line.hpp"
#include "roads.hpp"

using itp::Scalar;
using itp::geometry::CurveSample;
using itp::geometry::FrenetPoint;
using itp::geometry::Point2;
using itp::geometry::ReferenceLine;
using itp::geometry::ReferenceLineStatus;
using itp::geometry::SmoothingSplineWorkspace;
using test_roads::scalar_tol;

namespace {

SmoothingSplineWorkspace g_ws;

double angle_diff(Scalar a, Scalar b) {
  return std::fabs(static_cast<double>(itp::geometry::wrap_angle(a - b)));
}

struct FootErrors {
  double position = 0.0;  // max |foot.position - evaluate(s).position| [m]
  double heading = 0.0;   // [rad]
  double kappa = 0.0;     // [1/m]
  double dkappa = 0.0;    // [1/m^2]
  double normal = 0.0;    // max |p - (foot.position + l N(foot.heading))| [m]
  int points = 0;
};

// Points on a grid around the line, including 8 m beyond both ends.
FootErrors compare_with_evaluate(const ReferenceLine& line) {
  FootErrors e;
  const double length = static_cast<double>(line.length());
  for (double s = -8.0; s <= length + 8.0; s += 0.41) {
    const CurveSample c = line.evaluate(static_cast<Scalar>(s));
    const double h = static_cast<double>(c.heading);
    for (double l = -6.0; l <= 6.0; l += 0.75) {
      const Point2 p{static_cast<Scalar>(static_cast<double>(c.position.x) - l * std::sin(h)),
                     static_cast<Scalar>(static_cast<double>(c.position.y) + l * std::cos(h))};
      CurveSample foot;
      const FrenetPoint f = line.to_frenet(p, foot);
      const FrenetPoint g = line.to_frenet(p);
      // The same projection, bit for bit.
      CHECK(f.s == g.s);
      CHECK(f.l == g.l);
      const CurveSample r = line.evaluate(f.s);
      e.position = std::max(e.position, std::hypot(static_cast<double>(foot.position.x - r.position.x),
                                                   static_cast<double>(foot.position.y - r.position.y)));
      e.heading = std::max(e.heading, angle_diff(foot.heading, r.heading));
      e.kappa = std::max(e.kappa, std::fabs(static_cast<double>(foot.kappa - r.kappa)));
      e.dkappa = std::max(e.dkappa, std::fabs(static_cast<double>(foot.dkappa - r.dkappa)));
      // p is the foot point moved by l along the normal of the foot heading.
      const double fh = static_cast<double>(foot.heading);
      const double fl = static_cast<double>(f.l);
      e.normal = std::max(e.normal, std::hypot(static_cast<double>(foot.position.x) - fl * std::sin(fh) -
                                                   static_cast<double>(p.x),
                                               static_cast<double>(foot.position.y) + fl * std::cos(fh) -
                                                   static_cast<double>(p.y)));
      ++e.points;
    }
  }
  return e;
}

}  // namespace

TEST_CASE("to_frenet with the foot point equals to_frenet followed by evaluate(s)") {
  std::vector<std::vector<Point2>> roads;
  for (double spacing : {1.25, 5.0}) {
    roads.push_back(test_roads::straight({Scalar(12), Scalar(-7)}, 0.52, 120.0, spacing));
    roads.push_back(test_roads::Arc{30.0}.sample(100.0, spacing));
    roads.push_back(test_roads::Arc{200.0}.sample(100.0, spacing));
    roads.push_back(test_roads::SineRoad{}.sample(150.0, spacing));
  }
  for (const auto& pts : roads) {
    ReferenceLine line;
    REQUIRE(line.build(pts, g_ws) == ReferenceLineStatus::kOk);
    const FootErrors e = compare_with_evaluate(line);
    MESSAGE(pts.size() << " points, " << e.points << " projections: foot - evaluate(s): position "
                       << e.position << " m, heading " << e.heading << " rad, kappa " << e.kappa
                       << " 1/m, dkappa " << e.dkappa << " 1/m^2; p - (foot + l N) " << e.normal << " m");
    CHECK(e.position < scalar_tol(1e-9, 1e-3));
    CHECK(e.heading < scalar_tol(1e-9, 1e-4));
    CHECK(e.kappa < scalar_tol(1e-9, 1e-5));
    CHECK(e.dkappa < scalar_tol(1e-9, 1e-6));
    CHECK(e.normal < scalar_tol(1e-9, 1e-3));
  }
}

TEST_CASE("The foot point on an arc lies on the circle with the circle's heading and curvature") {
  for (double radius : {30.0, 50.0}) {
    const test_roads::Arc arc{radius};
    ReferenceLine line;
    REQUIRE(line.build(arc.sample(100.0, 2.0), g_ws) == ReferenceLineStatus::kOk);
    CAPTURE(radius);
    double worst_radius = 0.0;   // | |foot - centre| - R |
    double worst_heading = 0.0;  // foot heading against the exact tangent at the foot
    double worst_kappa = 0.0;    // |kappa R - 1|
    for (double s = 5.0; s <= 95.0; s += 0.7) {
      for (double l = -5.0; l <= 5.0; l += 1.25) {
        double x = 0.0;
        double y = 0.0;
        arc.frenet_to_xy(s, l, x, y);
        CurveSample foot;
        static_cast<void>(line.to_frenet({static_cast<Scalar>(x), static_cast<Scalar>(y)}, foot));
        const double fx = static_cast<double>(foot.position.x);
        const double fy = static_cast<double>(foot.position.y);
        worst_radius = std::max(worst_radius, std::fabs(std::hypot(fx, fy - radius) - radius));
        // Exact tangent direction of the circle at the foot's polar angle.
        const double phi = std::atan2(fx, radius - fy);
        worst_heading = std::max(worst_heading, angle_diff(foot.heading, static_cast<Scalar>(phi)));
        worst_kappa = std::max(worst_kappa, std::fabs(static_cast<double>(foot.kappa) * radius - 1.0));
      }
    }
    MESSAGE("R=" << radius << ": foot off the circle " << worst_radius << " m, heading " << worst_heading
                 << " rad, |kappa R - 1| " << worst_kappa);
    CHECK(worst_radius < 0.005);
    CHECK(worst_heading < 1e-3);
    CHECK(worst_kappa < 0.01);
  }
}

TEST_CASE("Beyond the ends the foot point is the straight extension, as evaluate(s) gives it") {
  const test_roads::Arc arc{50.0};
  ReferenceLine line;
  REQUIRE(line.build(arc.sample(60.0, 2.0), g_ws) == ReferenceLineStatus::kOk);
  CurveSample foot;
  const FrenetPoint f = line.to_frenet({Scalar(-5), Scalar(1)}, foot);
  CHECK(static_cast<double>(f.s) == doctest::Approx(-5.0).epsilon(1e-3));
  const CurveSample r = line.evaluate(f.s);
  CHECK(foot.position.x == r.position.x);
  CHECK(foot.position.y == r.position.y);
  CHECK(foot.heading == r.heading);
  CHECK(foot.kappa == Scalar(0));
  CHECK(foot.dkappa == Scalar(0));

  const CurveSample end = line.evaluate(line.length());
  const Point2 beyond{end.position.x + Scalar(7) * std::cos(end.heading) + Scalar(2) * std::sin(end.heading),
                      end.position.y + Scalar(7) * std::sin(end.heading) - Scalar(2) * std::cos(end.heading)};
  const FrenetPoint g = line.to_frenet(beyond, foot);
  CHECK(static_cast<double>(g.s - line.length()) == doctest::Approx(7.0).epsilon(1e-4));
  const CurveSample q = line.evaluate(g.s);
  CHECK(std::hypot(static_cast<double>(foot.position.x - q.position.x),
                   static_cast<double>(foot.position.y - q.position.y)) < scalar_tol(1e-9, 1e-4));
  CHECK(foot.heading == q.heading);
  CHECK(foot.kappa == Scalar(0));
}

TEST_CASE("Projection finds the globally nearest foot point on a road that comes back near itself") {
  // R = 20 m over 120 m: 344 degrees, the end passes 2 m outside the start,
  // so the coarse search must not stop at a locally near group of chords.
  const test_roads::Arc arc{20.0};
  ReferenceLine line;
  REQUIRE(line.build(arc.sample(120.0, 1.0), g_ws) == ReferenceLineStatus::kOk);
  const double length = static_cast<double>(line.length());
  // Brute force reference: the curve sampled every 5 cm, then refined.
  constexpr double kStep = 0.05;
  std::vector<Point2> dense;
  for (double s = 0.0; s <= length; s += kStep) {
    dense.push_back(line.evaluate(static_cast<Scalar>(s)).position);
  }
  int checked = 0;
  double worst_s = 0.0;  // |s - s_ref| [m]
  double worst_l = 0.0;  // ||l| - distance to the reference foot| [m]
  for (double x = -37.0; x <= 37.0; x += 1.13) {
    for (double y = -17.0; y <= 57.0; y += 1.07) {
      const Point2 p{static_cast<Scalar>(x), static_cast<Scalar>(y)};
      // Nearest sample, and the nearest one at least 3 m of arc away from it.
      const auto d2 = [&](std::size_t i) {
        const double dx = static_cast<double>(dense[i].x) - x;
        const double dy = static_cast<double>(dense[i].y) - y;
        return dx * dx + dy * dy;
      };
      std::size_t best = 0;
      for (std::size_t i = 1; i < dense.size(); ++i) {
        best = d2(i) < d2(best) ? i : best;
      }
      double other_d2 = 1e300;
      for (std::size_t i = 0; i < dense.size(); ++i) {
        if (kStep * std::fabs(static_cast<double>(i) - static_cast<double>(best)) >= 3.0) {
          other_d2 = std::min(other_d2, d2(i));
        }
      }
      const double best_d = std::sqrt(d2(best));
      const double other_d = std::sqrt(other_d2);
      const double best_s = kStep * static_cast<double>(best);
      // Only points with one clear nearest point, inside the ends and not
      // beyond the centre of curvature (docs/frenet.md, known limits).
      if (other_d - best_d < 0.5 || best_s < 1.0 || best_s > length - 1.0 || best_d > 15.0) {
        continue;
      }
      // Refine on evaluate(s) by golden-section search around the sample.
      const auto dist = [&](double s) {
        const Point2 c = line.evaluate(static_cast<Scalar>(s)).position;
        return std::hypot(static_cast<double>(c.x) - x, static_cast<double>(c.y) - y);
      };
      double lo = best_s - kStep;
      double hi = best_s + kStep;
      const double golden = 0.6180339887498949;
      for (int it = 0; it < 60; ++it) {
        const double a = hi - golden * (hi - lo);
        const double b = lo + golden * (hi - lo);
        if (dist(a) < dist(b)) {
          hi = b;
        } else {
          lo = a;
        }
      }
      const double ref_s = 0.5 * (lo + hi);
      const FrenetPoint f = line.to_frenet(p);
      worst_s = std::max(worst_s, std::fabs(static_cast<double>(f.s) - ref_s));
      worst_l = std::max(worst_l, std::fabs(std::fabs(static_cast<double>(f.l)) - dist(ref_s)));
      ++checked;
    }
  }
  MESSAGE(checked << " points: max |s - s_ref| = " << worst_s << " m, ||l| - d_ref| = " << worst_l << " m");
  CHECK(checked > 1000);
  // The golden section resolves s to ~3e-7 m in double, ~1 cm in float (flat
  // distance near its minimum); the other branch would be metres away.
  CHECK(worst_s < scalar_tol(1e-5, 0.02));
  CHECK(worst_l < scalar_tol(1e-6, 1e-3));
}

TEST_CASE("The foot-point projection does not allocate") {
  const std::vector<Point2> pts = test_roads::SineRoad{}.sample(120.0, 2.0);
  static ReferenceLine line;
  REQUIRE(line.build(pts, g_ws) == ReferenceLineStatus::kOk);
  test_support::HeapGuard guard;
  CurveSample foot;
  const FrenetPoint f = line.to_frenet({Scalar(40), Scalar(3)}, foot);
  CHECK(std::isfinite(f.s + f.l + foot.heading + foot.kappa));
}
