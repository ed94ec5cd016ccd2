// Oriented-box overlap and distance against brute force; polyline projection
// against analytic roads.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "sim/box_geometry.hpp"

using namespace hil::sim;

namespace {

double u01(std::mt19937_64& g) { return static_cast<double>(g() >> 11) * 0x1.0p-53; }
double uni(std::mt19937_64& g, double lo, double hi) { return lo + (hi - lo) * u01(g); }

OrientedBox random_box(std::mt19937_64& g) {
  return OrientedBox{uni(g, -4, 4), uni(g, -4, 4), uni(g, -4, 4), uni(g, 0.3, 5.0), uni(g, 0.3, 3.0)};
}

Point2 point_in(const OrientedBox& b, double u, double v) {  // u, v in [-1/2, 1/2]
  const double c = std::cos(b.heading), s = std::sin(b.heading);
  const double a = u * b.length, w = v * b.width;
  return {b.cx + a * c - w * s, b.cy + a * s + w * c};
}

// Independent exact overlap: a corner of one inside the other, or two edges cross.
bool segments_cross(Point2 a, Point2 b, Point2 c, Point2 d) {
  auto orient = [](Point2 p, Point2 q, Point2 r) {
    return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
  };
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  return ((o1 > 0) != (o2 > 0)) && ((o3 > 0) != (o4 > 0));
}
bool reference_overlap(const OrientedBox& a, const OrientedBox& b) {
  for (const auto& p : a.corners()) if (b.contains(p.x, p.y)) return true;
  for (const auto& p : b.corners()) if (a.contains(p.x, p.y)) return true;
  const auto ca = a.corners(), cb = b.corners();
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j)
      if (segments_cross(ca[i], ca[(i + 1) % 4], cb[j], cb[(j + 1) % 4])) return true;
  return false;
}

}  // namespace

TEST_CASE("SAT overlap agrees with brute-force point sampling and an exact reference") {
  std::mt19937_64 g(12345);
  int overlapping = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const OrientedBox a = random_box(g);
    const OrientedBox b = random_box(g);
    const bool sat = boxes_overlap(a, b);
    CHECK(sat == boxes_overlap(b, a));
    CHECK(sat == reference_overlap(a, b));
    // Brute force: a 25 x 25 grid of points inside A tested for containment in B.
    bool sampled = false;
    for (int i = 0; i <= 24 && !sampled; ++i)
      for (int j = 0; j <= 24 && !sampled; ++j) {
        const Point2 p = point_in(a, i / 24.0 - 0.5, j / 24.0 - 0.5);
        sampled = b.contains(p.x, p.y);
      }
    if (sampled) CHECK(sat);  // a shared point proves overlap
    if (!sat) CHECK(box_distance(a, b) > 0.0);
    else CHECK(box_distance(a, b) == 0.0);
    overlapping += sat ? 1 : 0;
  }
  CHECK(overlapping > 300);   // both outcomes well represented
  CHECK(overlapping < 2700);
}

TEST_CASE("box distance: exact on axis-aligned cases, symmetric, matches brute force") {
  const OrientedBox a{0, 0, 0, 4, 2};
  CHECK(box_distance(a, OrientedBox{6.3, 0, 0, 4, 2}) == doctest::Approx(2.3));         // along x
  CHECK(box_distance(a, OrientedBox{0.5, 3.5, 0, 4, 2}) == doctest::Approx(1.5));       // along y
  CHECK(box_distance(a, OrientedBox{7, 5, 0, 4, 2}) == doctest::Approx(std::hypot(3.0, 3.0)));  // corners
  CHECK(box_distance(a, OrientedBox{0, 2, 0, 4, 2}) == 0.0);                              // touching
  CHECK(boxes_overlap(a, OrientedBox{0, 2, 0, 4, 2}));
  // Rotated by 90 degrees: extents swap.
  CHECK(box_distance(a, OrientedBox{5, 0, std::numbers::pi / 2, 4, 2}) == doctest::Approx(2.0));

  std::mt19937_64 g(777);
  for (int trial = 0; trial < 300; ++trial) {
    const OrientedBox p = random_box(g);
    OrientedBox q = random_box(g);
    q.cx += 8.0;  // mostly disjoint
    const double d = box_distance(p, q);
    CHECK(d == doctest::Approx(box_distance(q, p)).epsilon(1e-12));
    if (d == 0.0) continue;
    // Brute force over boundary samples: never below the exact value, close to it.
    double brute = 1e9;
    std::vector<Point2> bp, bq;
    for (int i = 0; i <= 200; ++i) {
      const double u = i / 200.0 - 0.5;
      for (const double e : {-0.5, 0.5}) {
        bp.push_back(point_in(p, u, e));
        bp.push_back(point_in(p, e, u));
        bq.push_back(point_in(q, u, e));
        bq.push_back(point_in(q, e, u));
      }
    }
    for (const auto& x : bp)
      for (const auto& y : bq) brute = std::min(brute, std::hypot(x.x - y.x, x.y - y.y));
    CHECK(brute >= d - 1e-9);
    CHECK(brute <= d + 0.03);
  }
}

TEST_CASE("ego box: centre wheelbase/2 ahead of the rear axle by default") {
  const OrientedBox b = ego_box(Pose{1.0, 2.0, std::numbers::pi / 2}, 4.8, 1.9, 2.8);
  CHECK(b.cx == doctest::Approx(1.0));
  CHECK(b.cy == doctest::Approx(3.4));
  const OrientedBox c = ego_box(Pose{0, 0, 0}, 4.8, 1.9, 2.8, 0.5);  // explicit rear overhang
  CHECK(c.cx == doctest::Approx(1.9));
  Ego e;
  e.x = 10;
  CHECK(ego_box(e).cx == doctest::Approx(11.4));
}

TEST_CASE("lateral offset of a point: straight line exact, 2 m-sampled R = 50 m arc within 1 cm") {
  std::vector<Point2> straight;
  for (int i = 0; i <= 50; ++i) straight.push_back({2.0 * i, 0.0});
  CHECK(lateral_offset_of_point(straight, 13.3, 1.25) == doctest::Approx(1.25));
  CHECK(lateral_offset_of_point(straight, 13.3, -2.5) == doctest::Approx(-2.5));
  CHECK(project_to_polyline(straight, 13.3, 0.4).s == doctest::Approx(13.3));
  CHECK(project_to_polyline(straight, -3.0, 0.4).s == doctest::Approx(-3.0));  // extended start

  for (double radius : {50.0, 120.0, -50.0}) {
    const double r = std::abs(radius);
    const double sign = radius > 0 ? 1.0 : -1.0;  // left or right turn
    std::vector<Point2> arc;
    for (int i = 0; i <= 60; ++i) {
      const double phi = 2.0 * i / r;
      arc.push_back({r * std::sin(phi), sign * (r - r * std::cos(phi))});
    }
    double worst = 0.0;
    for (double s = 3.0; s < 115.0; s += 0.37) {
      for (double l : {-5.0, -1.75, 0.0, 0.9, 3.5, 5.25}) {
        const double phi = s / r;
        const double rr = r - sign * l;  // l > 0 is left: towards the centre of a left turn
        const double x = rr * std::sin(phi);
        const double y = sign * (r - rr * std::cos(phi));
        const PolylineProjection p = project_to_polyline(arc, x, y);
        worst = std::max(worst, std::abs(p.l - l));
        CHECK(p.s == doctest::Approx(s).epsilon(0.002));
      }
    }
    CHECK(worst < 0.01);
    MESSAGE("R = " << radius << ": worst |l error| = " << worst << " m");
  }
}
