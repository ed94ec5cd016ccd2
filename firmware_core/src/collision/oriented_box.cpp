#include "itp/collision/oriented_box.hpp"

#include <cmath>

namespace itp::collision {
namespace {

Scalar dot(Scalar ax, Scalar ay, Scalar bx, Scalar by) { return ax * bx + ay * by; }

// Do the projections of both boxes onto axis (ux, uy) leave a gap?
bool separated_on(const std::array<Corner, 4>& a, const std::array<Corner, 4>& b, Scalar ux, Scalar uy) {
  Scalar a_min = dot(a[0].x, a[0].y, ux, uy);
  Scalar a_max = a_min;
  Scalar b_min = dot(b[0].x, b[0].y, ux, uy);
  Scalar b_max = b_min;
  for (int i = 1; i < 4; ++i) {  // 4 corners
    const Scalar pa = dot(a[static_cast<std::size_t>(i)].x, a[static_cast<std::size_t>(i)].y, ux, uy);
    const Scalar pb = dot(b[static_cast<std::size_t>(i)].x, b[static_cast<std::size_t>(i)].y, ux, uy);
    a_min = pa < a_min ? pa : a_min;
    a_max = pa > a_max ? pa : a_max;
    b_min = pb < b_min ? pb : b_min;
    b_max = pb > b_max ? pb : b_max;
  }
  return a_max < b_min || b_max < a_min;
}

Scalar point_segment_distance(Corner p, Corner a, Corner b) {
  const Scalar ex = b.x - a.x;
  const Scalar ey = b.y - a.y;
  const Scalar len2 = ex * ex + ey * ey;
  Scalar u = len2 > 0 ? dot(p.x - a.x, p.y - a.y, ex, ey) / len2 : Scalar(0);
  u = u < 0 ? Scalar(0) : (u > 1 ? Scalar(1) : u);
  const Scalar dx = p.x - (a.x + u * ex);
  const Scalar dy = p.y - (a.y + u * ey);
  return std::sqrt(dx * dx + dy * dy);
}

}  // namespace

std::array<Corner, 4> corners(const OrientedBox& box) {
  const Scalar c = std::cos(box.heading);
  const Scalar s = std::sin(box.heading);
  const Scalar hl = Scalar(0.5) * box.length;
  const Scalar hw = Scalar(0.5) * box.width;
  const Scalar lx[4] = {hl, -hl, -hl, hl};
  const Scalar ly[4] = {hw, hw, -hw, -hw};
  std::array<Corner, 4> out{};
  for (int i = 0; i < 4; ++i) {  // 4 corners
    out[static_cast<std::size_t>(i)] = Corner{box.cx + c * lx[i] - s * ly[i], box.cy + s * lx[i] + c * ly[i]};
  }
  return out;
}

OrientedBox box_from_rear_axle(Scalar x, Scalar y, Scalar heading, Scalar length, Scalar width,
                               Scalar rear_overhang) {
  const Scalar ahead = Scalar(0.5) * length - rear_overhang;
  return OrientedBox{x + ahead * std::cos(heading), y + ahead * std::sin(heading), heading, length, width};
}

bool overlap(const OrientedBox& a, const OrientedBox& b) {
  // Circumscribed circles first: most pairs are far apart, and this skips
  // the trigonometry of the separating-axis test for them (exact: each
  // circle contains its box).
  const Scalar dx = a.cx - b.cx;
  const Scalar dy = a.cy - b.cy;
  const Scalar ra2 = Scalar(0.25) * (a.length * a.length + a.width * a.width);
  const Scalar rb2 = Scalar(0.25) * (b.length * b.length + b.width * b.width);
  const Scalar d2 = dx * dx + dy * dy;
  // (ra + rb)^2 <= 2 (ra^2 + rb^2): a cheap, still-exact upper bound without square roots.
  if (d2 > Scalar(2) * (ra2 + rb2)) {
    return false;
  }
  const auto ca = corners(a);
  const auto cb = corners(b);
  const Scalar axes[4][2] = {{std::cos(a.heading), std::sin(a.heading)},
                             {-std::sin(a.heading), std::cos(a.heading)},
                             {std::cos(b.heading), std::sin(b.heading)},
                             {-std::sin(b.heading), std::cos(b.heading)}};
  for (const auto& axis : axes) {  // 4 candidate separating axes
    if (separated_on(ca, cb, axis[0], axis[1])) {
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
  const auto ca = corners(a);
  const auto cb = corners(b);
  Scalar best = point_segment_distance(ca[0], cb[0], cb[1]);
  for (int i = 0; i < 4; ++i) {    // corners
    for (int j = 0; j < 4; ++j) {  // edges
      const auto ui = static_cast<std::size_t>(i);
      const auto j0 = static_cast<std::size_t>(j);
      const auto j1 = static_cast<std::size_t>((j + 1) % 4);
      const Scalar d1 = point_segment_distance(ca[ui], cb[j0], cb[j1]);
      const Scalar d2 = point_segment_distance(cb[ui], ca[j0], ca[j1]);
      best = d1 < best ? d1 : best;
      best = d2 < best ? d2 : best;
    }
  }
  return best;
}

}  // namespace itp::collision
