#pragma once
// The one oriented box of the firmware: vehicle and obstacle footprints in
// the world frame. Collision questions about boxes are in
// itp/collision/box_overlap.hpp; their SL rectangle in itp/geometry/frenet.hpp.
#include <array>
#include <cmath>

#include "itp/geometry/point.hpp"

namespace itp::geometry {

struct OrientedBox {
  Point2 center;                // [m] box centre
  Scalar heading = Scalar(0);   // [rad] direction of the length axis
  Scalar length = Scalar(0);    // [m] along heading
  Scalar width = Scalar(0);     // [m] across heading
};

// Counter-clockwise from the front-right corner: front-right, front-left,
// rear-left, rear-right. Corner k and k+1 (mod 4) bound edge k.
inline std::array<Point2, 4> corners(const OrientedBox& box) {
  const Point2 along{std::cos(box.heading), std::sin(box.heading)};
  const Point2 across{-along.y, along.x};
  const Scalar hl = box.length / Scalar(2);
  const Scalar hw = box.width / Scalar(2);
  return {box.center + hl * along + (-hw) * across, box.center + hl * along + hw * across,
          box.center + (-hl) * along + hw * across, box.center + (-hl) * along + (-hw) * across};
}

// A vehicle's box from its rear-axle pose: the centre lies
// (length / 2 - rear_overhang) ahead of the rear axle.
inline OrientedBox box_from_rear_axle(Point2 rear_axle, Scalar heading, Scalar length, Scalar width,
                                      Scalar rear_overhang) {
  const Scalar ahead = Scalar(0.5) * length - rear_overhang;
  return OrientedBox{{rear_axle.x + ahead * std::cos(heading), rear_axle.y + ahead * std::sin(heading)},
                     heading, length, width};
}

}  // namespace itp::geometry
