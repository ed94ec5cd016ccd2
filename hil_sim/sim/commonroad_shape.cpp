#include "sim/commonroad_shape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hil::sim {
namespace {

namespace cr = formats::commonroad;
using Part = cr::ShapePart;

// The box of the shape in a frame turned by phi: extents along u = (cos, sin)
// and v = (-sin, cos).
LocalBox box_in_frame(const cr::Shape& shape, double phi) {
  const double c = std::cos(phi);
  const double s = std::sin(phi);
  double u0 = std::numeric_limits<double>::infinity(), u1 = -u0, v0 = u0, v1 = -u0;
  auto take = [&](double x, double y, double r) {
    const double u = c * x + s * y;
    const double v = -s * x + c * y;
    u0 = std::min(u0, u - r);
    u1 = std::max(u1, u + r);
    v0 = std::min(v0, v - r);
    v1 = std::max(v1, v + r);
  };
  for (const Part& p : shape) {
    if (p.kind == Part::Kind::kCircle) {
      take(p.center.x, p.center.y, p.radius);
    } else if (p.kind == Part::Kind::kRectangle) {
      const double cr_ = std::cos(p.orientation);
      const double sr = std::sin(p.orientation);
      for (const double a : {-0.5, 0.5}) {
        for (const double b : {-0.5, 0.5}) {
          const double lx = a * p.length;
          const double ly = b * p.width;
          take(p.center.x + cr_ * lx - sr * ly, p.center.y + sr * lx + cr_ * ly, 0.0);
        }
      }
    } else {
      for (const cr::Vec2& q : p.points) take(q.x, q.y, 0.0);
    }
  }
  const double mu = 0.5 * (u0 + u1);
  const double mv = 0.5 * (v0 + v1);
  return LocalBox{u1 - u0, v1 - v0, phi, {c * mu - s * mv, s * mu + c * mv}};
}

// Directions worth trying: each rectangle's own, each polygon edge.
std::vector<double> candidate_angles(const cr::Shape& shape) {
  std::vector<double> out{0.0};
  for (const Part& p : shape) {
    if (p.kind == Part::Kind::kRectangle) out.push_back(p.orientation);
    if (p.kind == Part::Kind::kPolygon) {
      for (std::size_t i = 0; i < p.points.size(); ++i) {
        const cr::Vec2& a = p.points[i];
        const cr::Vec2& b = p.points[(i + 1) % p.points.size()];
        if (a.x != b.x || a.y != b.y) out.push_back(std::atan2(b.y - a.y, b.x - a.x));
      }
    }
  }
  return out;
}

}  // namespace

LocalBox bounding_box(const cr::Shape& shape, bool aligned) {
  LocalBox best = box_in_frame(shape, 0.0);
  if (aligned) return best;
  // The minimum-area box of a convex polygon has a side on one of its edges;
  // the shape's own edges include its hull's for a single polygon or rectangle.
  for (const double phi : candidate_angles(shape)) {
    const LocalBox b = box_in_frame(shape, phi);
    if (b.length * b.width < best.length * best.width - 1e-12) best = b;
  }
  return best;
}

Pose place(const LocalBox& box, double x, double y, double orientation) {
  const double c = std::cos(orientation);
  const double s = std::sin(orientation);
  return Pose{x + c * box.centre.x - s * box.centre.y, y + s * box.centre.x + c * box.centre.y,
              wrap_angle(orientation + box.heading_offset)};
}

}  // namespace hil::sim
