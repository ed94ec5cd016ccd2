#include "itp/collision/box_overlap.hpp"

#include <cmath>

namespace itp::collision {
namespace {

using geometry::Point2;
using Corners = std::array<Point2, 4>;

// Do the projections of both boxes onto `axis` leave a gap?
bool separated_on(const Corners& a, const Corners& b, Point2 axis) {
  Scalar a_min = geometry::dot(a[0], axis);
  Scalar a_max = a_min;
  Scalar b_min = geometry::dot(b[0], axis);
  Scalar b_max = b_min;
  for (std::size_t i = 1; i < 4; ++i) {  // 4 corners
    const Scalar pa = geometry::dot(a[i], axis);
    const Scalar pb = geometry::dot(b[i], axis);
    a_min = pa < a_min ? pa : a_min;
    a_max = pa > a_max ? pa : a_max;
    b_min = pb < b_min ? pb : b_min;
    b_max = pb > b_max ? pb : b_max;
  }
  return a_max < b_min || b_max < a_min;
}

Scalar point_segment_distance(Point2 p, Point2 a, Point2 b) {
  const Point2 e = b - a;
  const Scalar len2 = geometry::dot(e, e);
  Scalar u = len2 > 0 ? geometry::dot(p - a, e) / len2 : Scalar(0);
  u = u < 0 ? Scalar(0) : (u > 1 ? Scalar(1) : u);
  const Scalar dx = p.x - (a.x + u * e.x);
  const Scalar dy = p.y - (a.y + u * e.y);
  return std::sqrt(dx * dx + dy * dy);
}

}  // namespace

bool overlap(const OrientedBox& a, const OrientedBox& b) {
  // Circumscribed circles first: most pairs are far apart, and this skips
  // the trigonometry of the separating-axis test for them (exact: each
  // circle contains its box).
  const Point2 d = a.center - b.center;
  const Scalar ra2 = Scalar(0.25) * (a.length * a.length + a.width * a.width);
  const Scalar rb2 = Scalar(0.25) * (b.length * b.length + b.width * b.width);
  // (ra + rb)^2 <= 2 (ra^2 + rb^2): a cheap, still-exact upper bound without square roots.
  if (geometry::dot(d, d) > Scalar(2) * (ra2 + rb2)) {
    return false;
  }
  const Corners ca = geometry::corners(a);
  const Corners cb = geometry::corners(b);
  const Point2 axes[4] = {{std::cos(a.heading), std::sin(a.heading)},
                          {-std::sin(a.heading), std::cos(a.heading)},
                          {std::cos(b.heading), std::sin(b.heading)},
                          {-std::sin(b.heading), std::cos(b.heading)}};
  for (const Point2& axis : axes) {  // 4 candidate separating axes
    if (separated_on(ca, cb, axis)) {
      return false;
    }
  }
  return true;
}

Scalar distance(const OrientedBox& a, const OrientedBox& b) {
  if (overlap(a, b)) {
    return 0;
  }
  // Disjoint convex polygons: the closest pair involves a corner of one box.
  const Corners ca = geometry::corners(a);
  const Corners cb = geometry::corners(b);
  Scalar best = point_segment_distance(ca[0], cb[0], cb[1]);
  for (std::size_t i = 0; i < 4; ++i) {    // corners
    for (std::size_t j = 0; j < 4; ++j) {  // edges
      const std::size_t j1 = (j + 1) % 4;
      const Scalar d1 = point_segment_distance(ca[i], cb[j], cb[j1]);
      const Scalar d2 = point_segment_distance(cb[i], ca[j], ca[j1]);
      best = d1 < best ? d1 : best;
      best = d2 < best ? d2 : best;
    }
  }
  return best;
}

}  // namespace itp::collision
