#pragma once
// Analytic test roads: sampled polylines plus the exact Frenet coordinates
// of the curve they sample, computed independently of the code under test.
#include <algorithm>
#include <cmath>
#include <vector>

#include "itp/geometry/point.hpp"

namespace test_roads {

using itp::Scalar;
using itp::geometry::Point2;

// Tolerance helper: float builds lose ~1e-5 relative on 100 m coordinates.
constexpr double scalar_tol(double double_tol, double float_tol) {
  return sizeof(Scalar) == sizeof(float) ? float_tol : double_tol;
}

// Straight road from `origin` with heading `theta`, `length` long, sampled
// every `spacing` metres (last point exactly at `length`).
inline std::vector<Point2> straight(Point2 origin, double theta, double length, double spacing) {
  std::vector<Point2> pts;
  const int n = static_cast<int>(std::ceil(length / spacing - 1e-9));
  for (int i = 0; i <= n; ++i) {
    const double s = std::min(length, i * spacing);
    pts.push_back({static_cast<Scalar>(static_cast<double>(origin.x) + s * std::cos(theta)),
                   static_cast<Scalar>(static_cast<double>(origin.y) + s * std::sin(theta))});
  }
  return pts;
}

// Left-turning arc of radius R starting at (0,0) heading +x; centre (0, R).
struct Arc {
  double radius;
  Point2 at(double s) const {
    const double phi = s / radius;
    return {static_cast<Scalar>(radius * std::sin(phi)),
            static_cast<Scalar>(radius - radius * std::cos(phi))};
  }
  // Cartesian point of Frenet (s, l): l > 0 towards the centre.
  void frenet_to_xy(double s, double l, double& x, double& y) const {
    const double phi = s / radius;
    x = (radius - l) * std::sin(phi);
    y = radius - (radius - l) * std::cos(phi);
  }
  // Exact Frenet coordinates of (x, y): s = R * angle, l = R - |p - centre|.
  // The angle is unwrapped to the turn nearest to `s_hint` (arcs may exceed
  // half a circle).
  void xy_to_frenet(double x, double y, double& s, double& l, double s_hint = 0.0) const {
    const double two_pi = 2.0 * 3.14159265358979323846;
    double phi = std::atan2(x, radius - y);
    phi += two_pi * std::round((s_hint / radius - phi) / two_pi);
    s = radius * phi;
    l = radius - std::hypot(x, y - radius);
  }
  std::vector<Point2> sample(double length, double spacing) const {
    std::vector<Point2> pts;
    const int n = static_cast<int>(std::ceil(length / spacing - 1e-9));
    for (int i = 0; i <= n; ++i) {
      pts.push_back(at(std::min(length, i * spacing)));
    }
    return pts;
  }
};

// S-curve y = A sin(k x): curvature A k^2 at the crests (radius 30.6 m for
// A = 10 m, wavelength 110 m), changing sign twice per wavelength.
struct SineRoad {
  double amplitude = 10.0;
  double k = 2.0 * 3.14159265358979323846 / 110.0;
  double y(double x) const { return amplitude * std::sin(k * x); }
  double dy(double x) const { return amplitude * k * std::cos(k * x); }
  double ddy(double x) const { return -amplitude * k * k * std::sin(k * x); }
  // Arc length from x = 0 to x: a table of cumulative lengths every 0.5 m
  // plus composite Simpson (8 panels) on the remainder; an independent
  // reference accurate to ~1e-12 m.
  double simpson(double a, double b) const {
    const int n = 8;
    const double h = (b - a) / n;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double xi = a + i * h;
      const double f = std::sqrt(1.0 + dy(xi) * dy(xi));
      sum += (i == 0 || i == n) ? f : (i % 2 == 1 ? 4.0 * f : 2.0 * f);
    }
    return sum * h / 3.0;
  }
  double arc_length(double x) const {
    constexpr double kStep = 0.5;
    if (table_.empty()) {
      table_.push_back(0.0);
      for (int i = 1; i * kStep <= 400.0; ++i) {
        table_.push_back(table_.back() + simpson((i - 1) * kStep, i * kStep));
      }
    }
    const int i = std::clamp(static_cast<int>(std::floor(x / kStep)), 0,
                             static_cast<int>(table_.size()) - 1);
    return table_[static_cast<std::size_t>(i)] + simpson(i * kStep, x);
  }
  // x at arc length s (Newton on arc_length).
  double x_at(double s) const {
    double x = s * 0.9;
    for (int i = 0; i < 30; ++i) {
      const double step = (arc_length(x) - s) / std::sqrt(1.0 + dy(x) * dy(x));
      x -= step;
      if (std::fabs(step) < 1e-13) break;
    }
    return x;
  }
  mutable std::vector<double> table_;
  // Samples every `spacing` of arc length up to `length`.
  std::vector<Point2> sample(double length, double spacing) const {
    std::vector<Point2> pts;
    const int n = static_cast<int>(std::ceil(length / spacing - 1e-9));
    for (int i = 0; i <= n; ++i) {
      const double x = x_at(std::min(length, i * spacing));
      pts.push_back({static_cast<Scalar>(x), static_cast<Scalar>(y(x))});
    }
    return pts;
  }
  // Exact Frenet coordinates of (px, py) near the curve: Newton on the foot
  // point (x - px) + (y(x) - py) y'(x) = 0 from x0.
  void xy_to_frenet(double px, double py, double x0, double& s, double& l) const {
    double x = x0;
    for (int i = 0; i < 50; ++i) {
      const double g = (x - px) + (y(x) - py) * dy(x);
      const double dg = 1.0 + dy(x) * dy(x) + (y(x) - py) * ddy(x);
      x -= g / dg;
      if (std::fabs(g / dg) < 1e-14) break;
    }
    const double norm_t = std::sqrt(1.0 + dy(x) * dy(x));
    const double tx = 1.0 / norm_t;
    const double ty = dy(x) / norm_t;
    s = arc_length(x);
    l = tx * (py - y(x)) - ty * (px - x);
  }
};

}  // namespace test_roads
