// cartesian_motion against finite differences of the world-frame position.
// The reference is a real ReferenceLine through an S-curve (curvature and its
// derivative both nonzero); the point r(t) = c(s(t)) + l(s(t)) N(s(t)) is
// built from the line's position and heading alone, and its speed,
// acceleration (d|v|/dt), heading and curvature are differentiated
// numerically, independently of the formula under test.
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "itp/geometry/angle.hpp"
#include "itp/geometry/frenet.hpp"
#include "itp/geometry/reference_line.hpp"

using namespace itp::geometry;
using itp::Scalar;

namespace {

// An S-curve: curvature 1/40 m for 60 m, then -1/50 m, joined smoothly.
std::vector<Point2> s_curve() {
  std::vector<Point2> pts;
  double x = 0, y = 0, th = 0;
  const double step = 2.0;
  for (double s = 0; s <= 200; s += step) {
    pts.push_back({x, y});
    const double k = s < 60 ? 1.0 / 40 : (s < 90 ? 1.0 / 40 + (s - 60) / 30 * (-1.0 / 50 - 1.0 / 40) : -1.0 / 50);
    const double thm = th + 0.5 * k * step;
    x += step * std::cos(thm);
    y += step * std::sin(thm);
    th += k * step;
  }
  return pts;
}

struct Motion {
  double s0, v0, a0, j0;     // s(t) = s0 + v0 t + a0 t^2 / 2 + j0 t^3 / 6
  double amp, period, off;   // l(s) = off + amp sin(2 pi (s - s0) / period)
  double s(double t) const { return s0 + v0 * t + 0.5 * a0 * t * t + j0 * t * t * t / 6; }
  double ds(double t) const { return v0 + a0 * t + 0.5 * j0 * t * t; }
  double dds(double t) const { return a0 + j0 * t; }
  double w() const { return 2 * M_PI / period; }
  double l(double s) const { return off + amp * std::sin(w() * (s - s0)); }
  double dl(double s) const { return amp * w() * std::cos(w() * (s - s0)); }
  double ddl(double s) const { return -amp * w() * w() * std::sin(w() * (s - s0)); }
};

}  // namespace

TEST_CASE("cartesian_motion: speed, dv/dt, heading and curvature match finite differences") {
  auto line = std::make_unique<ReferenceLine>();
  auto ws = std::make_unique<SmoothingSplineWorkspace>();
  const std::vector<Point2> pts = s_curve();
  REQUIRE(line->build(pts, *ws) == ReferenceLineStatus::kOk);
  const Motion m{20.0, 9.0, -1.5, 0.4, 1.2, 35.0, 0.6};
  const auto position = [&](double t) {
    const double s = m.s(t);
    const CurveSample r = line->evaluate(s);
    const double l = m.l(s);
    return Point2{r.position.x - l * std::sin(r.heading), r.position.y + l * std::cos(r.heading)};
  };
  const double h = 1e-3;  // [s]
  const auto velocity = [&](double t) {  // 4th-order central difference
    const Point2 a = position(t - 2 * h), b = position(t - h), c = position(t + h), d = position(t + 2 * h);
    return Point2{(a.x - 8 * b.x + 8 * c.x - d.x) / (12 * h), (a.y - 8 * b.y + 8 * c.y - d.y) / (12 * h)};
  };
  const auto speed = [&](double t) { return norm(velocity(t)); };
  double worst_a = 0;
  for (double t = 0.2; t < 6.0; t += 0.37) {
    const double s = m.s(t);
    const CurveSample r = line->evaluate(s);
    FrenetState f;
    f.ds = m.ds(t);
    f.dds = m.dds(t);
    f.l = m.l(s);
    f.dl = m.dl(s);
    f.ddl = m.ddl(s);
    f.ref_kappa = r.kappa;
    f.ref_dkappa = r.dkappa;
    const CartesianMotion c = cartesian_motion(f);
    const Point2 v = velocity(t);
    CHECK(c.v == doctest::Approx(norm(v)).epsilon(1e-6));
    const double dvdt = (speed(t - 2 * h) - 8 * speed(t - h) + 8 * speed(t + h) - speed(t + 2 * h)) / (12 * h);
    CHECK(std::fabs(c.a - dvdt) < 1e-3);
    worst_a = std::max(worst_a, std::fabs(c.a - dvdt));
    CHECK(std::fabs(wrap_angle(r.heading + c.relative_heading - std::atan2(v.y, v.x))) < 1e-6);
    // Curvature: heading change per metre travelled.
    const Point2 v1 = velocity(t + h);
    const Point2 v0 = velocity(t - h);
    const double dtheta = wrap_angle(std::atan2(v1.y, v1.x) - std::atan2(v0.y, v0.x));
    CHECK(c.kappa == doctest::Approx(dtheta / (2 * h * norm(v))).epsilon(1e-4).scale(1e-3));
  }
  MESSAGE("largest |a - dv/dt|: " << worst_a << " m/s^2");
  // The small-angle reading a = s'' (1 - kappa l) / cos(dtheta), used before,
  // misses the s'^2 g' term: this motion makes it err by far more than 1e-3.
  const double t = 1.0;
  const double s = m.s(t);
  const CurveSample r = line->evaluate(s);
  const double q = 1 - r.kappa * m.l(s);
  const double old_a = m.dds(t) * q / std::cos(std::atan2(m.dl(s), q));
  const double dvdt = (speed(t - 2 * h) - 8 * speed(t - h) + 8 * speed(t + h) - speed(t + 2 * h)) / (12 * h);
  CHECK(std::fabs(old_a - dvdt) > 0.05);
}
