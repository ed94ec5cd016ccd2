// SL bounding rectangle of oriented boxes and heading <-> l' conversion.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "itp/geometry/angle.hpp"
#include "itp/geometry/frenet.hpp"
#include "roads.hpp"

using itp::Scalar;
using itp::geometry::OrientedBox;
using itp::geometry::Point2;
using itp::geometry::ReferenceLine;
using itp::geometry::ReferenceLineStatus;
using itp::geometry::SlBox;
using itp::geometry::SmoothingSplineWorkspace;

namespace {
SmoothingSplineWorkspace g_ws;
}

TEST_CASE("SL box of a box on a straight road is the rotated box, with margin") {
  ReferenceLine line;
  REQUIRE(line.build(test_roads::straight({Scalar(0), Scalar(0)}, 0.0, 100.0, 5.0), g_ws) ==
          ReferenceLineStatus::kOk);
  // Axis-aligned: exactly [35.5, 44.5] x [-0.6, 1.2].
  const SlBox a = sl_bounding_box(line, {{Scalar(40), Scalar(0.3)}, Scalar(0), Scalar(9), Scalar(1.8)},
                                  Scalar(0));
  CHECK(static_cast<double>(a.s_min) == doctest::Approx(35.5));
  CHECK(static_cast<double>(a.s_max) == doctest::Approx(44.5));
  CHECK(static_cast<double>(a.l_min) == doctest::Approx(-0.6));
  CHECK(static_cast<double>(a.l_max) == doctest::Approx(1.2));
  // Rotated by 90 deg with a 0.5 m margin.
  const SlBox b = sl_bounding_box(
      line, {{Scalar(40), Scalar(0)}, itp::geometry::kPi / Scalar(2), Scalar(4), Scalar(2)}, Scalar(0.5));
  CHECK(static_cast<double>(b.s_min) == doctest::Approx(38.5));
  CHECK(static_cast<double>(b.s_max) == doctest::Approx(41.5));
  CHECK(static_cast<double>(b.l_min) == doctest::Approx(-2.5));
  CHECK(static_cast<double>(b.l_max) == doctest::Approx(2.5));
}

TEST_CASE("SL box of a long box on a curved road covers its densely sampled outline") {
  const test_roads::Arc arc{30.0};
  ReferenceLine line;
  REQUIRE(line.build(arc.sample(90.0, 2.0), g_ws) == ReferenceLineStatus::kOk);
  // An 18 m truck tangent to the arc at s = 40, 2 m to the right: its middle
  // bulges towards the centre's far side, so l_min lies inside an edge.
  const Point2 c = arc.at(40.0);
  const double heading = 40.0 / 30.0;
  const OrientedBox box{{c.x + Scalar(2 * std::sin(heading)), c.y - Scalar(2 * std::cos(heading))},
                        static_cast<Scalar>(heading), Scalar(18), Scalar(2.5)};
  const SlBox sl = sl_bounding_box(line, box, Scalar(0));
  // Independent reference: exact polar coordinates of 400 points per edge.
  double s_min = 1e9, s_max = -1e9, l_min = 1e9, l_max = -1e9;
  const double ca = std::cos(heading), sa = std::sin(heading);
  for (int k = 0; k < 4; ++k) {
    for (int j = 0; j <= 400; ++j) {
      const double f = j / 400.0;
      double u = 0.0, v = 0.0;  // box-local coordinates along the outline
      if (k == 0) { u = 9.0; v = -1.25 + 2.5 * f; }
      if (k == 1) { u = 9.0 - 18.0 * f; v = 1.25; }
      if (k == 2) { u = -9.0; v = 1.25 - 2.5 * f; }
      if (k == 3) { u = -9.0 + 18.0 * f; v = -1.25; }
      const double x = static_cast<double>(box.center.x) + u * ca - v * sa;
      const double y = static_cast<double>(box.center.y) + u * sa + v * ca;
      double s = 0.0, l = 0.0;
      arc.xy_to_frenet(x, y, s, l);
      s_min = std::min(s_min, s); s_max = std::max(s_max, s);
      l_min = std::min(l_min, l); l_max = std::max(l_max, l);
    }
  }
  // Corners alone would miss the bulge: l at the edge middle is ~1.35 m
  // lower than at its corners. Sampling every <= 1 m leaves < 1 cm.
  CHECK(static_cast<double>(sl.s_min) == doctest::Approx(s_min).epsilon(0).scale(0).epsilon(1e-3));
  CHECK(std::fabs(static_cast<double>(sl.s_min) - s_min) < 0.01);
  CHECK(std::fabs(static_cast<double>(sl.s_max) - s_max) < 0.01);
  CHECK(std::fabs(static_cast<double>(sl.l_min) - l_min) < 0.01);
  CHECK(std::fabs(static_cast<double>(sl.l_max) - l_max) < 0.01);
}

TEST_CASE("Heading <-> l' conversion: l' = (1 - kappa l) tan(dtheta) and back") {
  // On a straight road l' = tan(dtheta).
  CHECK(static_cast<double>(itp::geometry::lateral_slope(Scalar(0.3), Scalar(0.1), Scalar(0), Scalar(2))) ==
        doctest::Approx(std::tan(0.2)));
  // On an arc of radius 50 m at l = 2 m: factor (1 - 2/50).
  const Scalar lp = itp::geometry::lateral_slope(Scalar(1.2), Scalar(1.0), Scalar(0.02), Scalar(2));
  CHECK(static_cast<double>(lp) == doctest::Approx(0.96 * std::tan(0.2)).epsilon(1e-5));
  const Scalar back = itp::geometry::heading_from_lateral_slope(lp, Scalar(1.0), Scalar(0.02), Scalar(2));
  CHECK(static_cast<double>(back) == doctest::Approx(1.2).epsilon(1e-5));
  // Wrap-around: headings either side of +-pi.
  CHECK(static_cast<double>(itp::geometry::relative_heading(Scalar(-3.1), Scalar(3.1))) ==
        doctest::Approx(2.0 * 3.14159265358979 - 6.2).epsilon(1e-5));

  // Geometric check: a straight path at heading theta crossing an arc. Its
  // l(s) measured through the reference line has slope l' from the formula.
  const test_roads::Arc arc{50.0};
  ReferenceLine line;
  REQUIRE(line.build(arc.sample(80.0, 2.0), g_ws) == ReferenceLineStatus::kOk);
  const Point2 p0 = line.to_cartesian({Scalar(30), Scalar(1.5)});
  const auto ref = line.evaluate(Scalar(30));
  const Scalar theta = ref.heading + Scalar(0.15);
  const Scalar h = Scalar(0.01);
  const Point2 dir{std::cos(theta), std::sin(theta)};
  const auto fa = line.to_frenet(p0 + h * dir);
  const auto fb = line.to_frenet(p0 + (-h) * dir);
  const double numeric = static_cast<double>((fa.l - fb.l) / (fa.s - fb.s));
  const double formula =
      static_cast<double>(itp::geometry::lateral_slope(theta, ref.heading, ref.kappa, Scalar(1.5)));
  CHECK(numeric == doctest::Approx(formula).epsilon(1e-3));
}
