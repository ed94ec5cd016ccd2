#pragma once
// Plain 2-D value types shared by the geometry and scene code.
#include <cmath>

#include "itp/config.hpp"

namespace itp::geometry {

// A point in the Cartesian world frame.
struct Point2 {
  Scalar x = Scalar(0);  // [m]
  Scalar y = Scalar(0);  // [m]
};

// A point in the Frenet frame of a ReferenceLine.
struct FrenetPoint {
  Scalar s = Scalar(0);  // [m] arc length along the smoothed reference curve
  Scalar l = Scalar(0);  // [m] signed lateral offset, positive to the left
};

constexpr Point2 operator+(Point2 a, Point2 b) { return {a.x + b.x, a.y + b.y}; }
constexpr Point2 operator-(Point2 a, Point2 b) { return {a.x - b.x, a.y - b.y}; }
constexpr Point2 operator*(Scalar k, Point2 a) { return {k * a.x, k * a.y}; }
constexpr Scalar dot(Point2 a, Point2 b) { return a.x * b.x + a.y * b.y; }
// z-component of the 3-D cross product: > 0 when b lies to the left of a.
constexpr Scalar cross(Point2 a, Point2 b) { return a.x * b.y - a.y * b.x; }
inline Scalar norm(Point2 a) { return std::sqrt(dot(a, a)); }

inline bool is_finite(Point2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }

}  // namespace itp::geometry
