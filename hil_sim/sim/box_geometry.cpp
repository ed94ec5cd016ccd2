#include "sim/box_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hil::sim {

namespace {
double dot(Point2 a, Point2 b) { return a.x * b.x + a.y * b.y; }
double cross(Point2 a, Point2 b) { return a.x * b.y - a.y * b.x; }
Point2 sub(Point2 a, Point2 b) { return {a.x - b.x, a.y - b.y}; }

// Signed curvature through three points (Menger), left turn positive.
double menger_curvature(Point2 a, Point2 b, Point2 c) {
  const double ab = std::hypot(b.x - a.x, b.y - a.y);
  const double bc = std::hypot(c.x - b.x, c.y - b.y);
  const double ca = std::hypot(a.x - c.x, a.y - c.y);
  const double den = ab * bc * ca;
  if (den <= 1e-12) {
    return 0.0;
  }
  return 2.0 * cross(sub(b, a), sub(c, a)) / den;
}
}  // namespace

std::array<Point2, 4> OrientedBox::corners() const {
  const double c = std::cos(heading);
  const double s = std::sin(heading);
  const double hl = 0.5 * length;
  const double hw = 0.5 * width;
  auto at = [&](double u, double v) { return Point2{cx + u * c - v * s, cy + u * s + v * c}; };
  return {at(-hl, -hw), at(hl, -hw), at(hl, hw), at(-hl, hw)};
}

bool OrientedBox::contains(double x, double y, double tol) const {
  const double c = std::cos(heading);
  const double s = std::sin(heading);
  const double dx = x - cx;
  const double dy = y - cy;
  const double u = dx * c + dy * s;
  const double v = -dx * s + dy * c;
  return std::abs(u) <= 0.5 * length + tol && std::abs(v) <= 0.5 * width + tol;
}

bool boxes_overlap(const OrientedBox& a, const OrientedBox& b) {
  const auto ca = a.corners();
  const auto cb = b.corners();
  const std::array<Point2, 4> axes = {Point2{std::cos(a.heading), std::sin(a.heading)},
                                      Point2{-std::sin(a.heading), std::cos(a.heading)},
                                      Point2{std::cos(b.heading), std::sin(b.heading)},
                                      Point2{-std::sin(b.heading), std::cos(b.heading)}};
  for (const Point2& ax : axes) {
    double amin = std::numeric_limits<double>::infinity();
    double amax = -amin;
    double bmin = amin;
    double bmax = -amin;
    for (int i = 0; i < 4; ++i) {
      const double pa = dot(ca[static_cast<std::size_t>(i)], ax);
      const double pb = dot(cb[static_cast<std::size_t>(i)], ax);
      amin = std::min(amin, pa);
      amax = std::max(amax, pa);
      bmin = std::min(bmin, pb);
      bmax = std::max(bmax, pb);
    }
    if (amax < bmin || bmax < amin) {
      return false;  // a separating axis exists
    }
  }
  return true;
}

double point_segment_distance(Point2 p, Point2 a, Point2 b) {
  const Point2 ab = sub(b, a);
  const double len2 = dot(ab, ab);
  double u = len2 > 0.0 ? dot(sub(p, a), ab) / len2 : 0.0;
  u = std::clamp(u, 0.0, 1.0);
  return std::hypot(p.x - (a.x + u * ab.x), p.y - (a.y + u * ab.y));
}

double box_distance(const OrientedBox& a, const OrientedBox& b) {
  if (boxes_overlap(a, b)) {
    return 0.0;
  }
  const auto ca = a.corners();
  const auto cb = b.corners();
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < 4; ++i) {
    const std::size_t j = (i + 1) % 4;
    for (std::size_t k = 0; k < 4; ++k) {
      d = std::min(d, point_segment_distance(ca[k], cb[i], cb[j]));
      d = std::min(d, point_segment_distance(cb[k], ca[i], ca[j]));
    }
  }
  return d;
}

OrientedBox ego_box(const Pose& rear_axle, double length, double width, double wheelbase,
                    double rear_overhang) {
  const double overhang = rear_overhang >= 0.0 ? rear_overhang : 0.5 * (length - wheelbase);
  const double ahead = 0.5 * length - overhang;  // rear axle -> box centre
  return OrientedBox{rear_axle.x + ahead * std::cos(rear_axle.heading),
                     rear_axle.y + ahead * std::sin(rear_axle.heading), rear_axle.heading, length,
                     width};
}

OrientedBox ego_box(const Ego& e) {
  return ego_box(Pose{e.x, e.y, e.heading}, e.length, e.width, e.wheelbase);
}

OrientedBox obstacle_box(const StaticObstacle& o) {
  return OrientedBox{o.x, o.y, o.heading, o.length, o.width};
}

OrientedBox obstacle_box(const DynamicObstacle& o, const Pose& c) {
  return OrientedBox{c.x, c.y, c.heading, o.length, o.width};
}

std::vector<double> polyline_arc_lengths(std::span<const Point2> pl) {
  std::vector<double> s(pl.size(), 0.0);
  for (std::size_t i = 1; i < pl.size(); ++i) {
    s[i] = s[i - 1] + std::hypot(pl[i].x - pl[i - 1].x, pl[i].y - pl[i - 1].y);
  }
  return s;
}

PolylineProjection project_to_polyline(std::span<const Point2> pl, double x, double y) {
  PolylineProjection best;
  if (pl.size() < 2) {
    return best;
  }
  const Point2 p{x, y};
  const std::size_t nseg = pl.size() - 1;
  double best_d2 = std::numeric_limits<double>::infinity();
  double s_acc = 0.0;
  double best_u = 0.0;
  double best_len = 0.0;
  double best_s0 = 0.0;
  for (std::size_t i = 0; i < nseg; ++i) {
    const Point2 a = pl[i];
    const Point2 ab = sub(pl[i + 1], a);
    const double len = std::sqrt(dot(ab, ab));
    if (len <= 0.0) {
      continue;
    }
    double u = dot(sub(p, a), ab) / (len * len);
    // Only the first and last segments extend beyond their ends.
    const double lo = (i == 0) ? -std::numeric_limits<double>::infinity() : 0.0;
    const double hi = (i + 1 == nseg) ? std::numeric_limits<double>::infinity() : 1.0;
    const double uc = std::clamp(u, lo, hi);
    const double fx = a.x + uc * ab.x;
    const double fy = a.y + uc * ab.y;
    const double d2 = (p.x - fx) * (p.x - fx) + (p.y - fy) * (p.y - fy);
    if (d2 < best_d2) {
      best_d2 = d2;
      best.segment = i;
      best_u = uc;
      best_len = len;
      best_s0 = s_acc;
    }
    s_acc += len;
  }
  const std::size_t i = best.segment;
  const Point2 a = pl[i];
  const Point2 ab = sub(pl[i + 1], a);
  const double l_chord = cross(ab, sub(p, a)) / best_len;
  // Local curvature from the neighbouring vertices (Menger), averaged.
  double kappa = 0.0;
  int nk = 0;
  if (i >= 1) {
    kappa += menger_curvature(pl[i - 1], pl[i], pl[i + 1]);
    ++nk;
  }
  if (i + 2 < pl.size()) {
    kappa += menger_curvature(pl[i], pl[i + 1], pl[i + 2]);
    ++nk;
  }
  if (nk > 0) {
    kappa /= nk;
  }
  const double chord_heading = std::atan2(ab.y, ab.x);
  if (std::abs(kappa) * best_len < 1e-6) {
    best.l = l_chord;
    best.s = best_s0 + best_u * best_len;
    best.heading = chord_heading;
    return best;
  }
  // Treat the segment as the circular arc of curvature kappa through its two
  // vertices: exact s and l for constant curvature, continuous across vertices.
  const double radius = 1.0 / kappa;  // signed, left turn positive
  const double half = 0.5 * best_len;
  const double h = std::sqrt(std::max(radius * radius - half * half, 0.0));
  const Point2 mid{a.x + 0.5 * ab.x, a.y + 0.5 * ab.y};
  const Point2 nl{-ab.y / best_len, ab.x / best_len};  // left normal of the chord
  const double side = kappa > 0.0 ? 1.0 : -1.0;
  const Point2 centre{mid.x + side * h * nl.x, mid.y + side * h * nl.y};
  const Point2 ca = sub(a, centre);
  const Point2 cp = sub(p, centre);
  const double phi = std::atan2(cross(ca, cp), dot(ca, cp));  // CCW angle a -> p about the centre
  const double arc_angle = 2.0 * std::asin(std::min(1.0, half / std::abs(radius)));
  const double arc_len = arc_angle * std::abs(radius);
  best.l = side * (std::abs(radius) - std::sqrt(dot(cp, cp)));
  // Arc length from a along the arc, rescaled so the vertices keep their chord-based s.
  best.s = best_s0 + (phi / kappa) * (best_len / arc_len);
  best.heading = wrap_angle(chord_heading - 0.5 * kappa * arc_len + phi);
  return best;
}

Pose polyline_pose(std::span<const Point2> pl, std::span<const double> sv, double s, double l) {
  const std::size_t n = pl.size();
  std::size_t i = 0;
  if (s >= sv[n - 1]) {
    i = n - 2;
  } else if (s > 0.0) {
    const auto it = std::upper_bound(sv.begin(), sv.end(), s);
    i = static_cast<std::size_t>(it - sv.begin()) - 1;
    i = std::min(i, n - 2);
  }
  const Point2 a = pl[i];
  const Point2 b = pl[i + 1];
  const double len = sv[i + 1] - sv[i];
  const double u = len > 0.0 ? (s - sv[i]) / len : 0.0;
  const double h = std::atan2(b.y - a.y, b.x - a.x);
  return Pose{a.x + u * (b.x - a.x) - l * std::sin(h), a.y + u * (b.y - a.y) + l * std::cos(h), h};
}

}  // namespace hil::sim
