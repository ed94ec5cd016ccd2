// Cartesian <-> Frenet conversion on the smoothed reference curve.
#include <algorithm>
#include <cmath>
#include <limits>

#include "itp/core/assert.hpp"
#include "itp/geometry/reference_line.hpp"

namespace itp::geometry {

// Foot point of p on the curve C(u), u in [t_first, t_last]:
//  1. coarse: the nearest chord between consecutive knots (all real segments,
//     at most kMaxReferencePoints - 1), giving a start u0;
//  2. Newton on g(u) = (C(u) - p) . C'(u) = 0, g'(u) = |C'|^2 + (C - p) . C''
//     (at most kProjectionNewtonSteps; |l| < 1/|kappa| keeps g' > 0, else the
//     step falls back to Gauss-Newton), clamped to the curve's ends.
// Then s = s(u), l = T x (p - C). A point beyond an end is expressed in the
// straight extension of that end, exactly as to_cartesian extends it.
FrenetPoint ReferenceLine::to_frenet(Point2 p) const {
  ITP_EXPECTS(valid_);
  int best_segment = first_;
  Scalar best_tau = Scalar(0);
  Scalar best_d2 = std::numeric_limits<Scalar>::max();
  for (int i = first_; i < last_ && i < config::kMaxReferenceKnots; ++i) {
    const Point2 a{x_[i], y_[i]};
    const Point2 d{x_[i + 1] - x_[i], y_[i + 1] - y_[i]};
    const Scalar tau = std::clamp(dot(p - a, d) / dot(d, d), Scalar(0), Scalar(1));
    const Point2 e = p - (a + tau * d);
    const Scalar d2 = dot(e, e);
    if (d2 < best_d2) {
      best_d2 = d2;
      best_segment = i;
      best_tau = tau;
    }
  }
  const Scalar u_min = t_[first_];
  const Scalar u_max = t_[last_];
  Scalar u = t_[best_segment] + best_tau * (t_[best_segment + 1] - t_[best_segment]);
  const Scalar tolerance = Scalar(8) * std::numeric_limits<Scalar>::epsilon() * (Scalar(1) + u_max);
  for (int it = 0; it < config::kProjectionNewtonSteps; ++it) {
    const Derivatives d = derivatives(segment_of_parameter(u), u);
    const Point2 e = d.p - p;
    const Scalar g = dot(e, d.d1);
    const Scalar speed2 = dot(d.d1, d.d1);
    Scalar dg = speed2 + dot(e, d.d2);
    if (dg < Scalar(0.1) * speed2) {
      dg = speed2;  // near the centre of curvature: Gauss-Newton step
    }
    const Scalar next = std::clamp(u - g / dg, u_min, u_max);
    const Scalar step = next - u;
    u = next;
    if (std::fabs(step) <= tolerance) {
      break;
    }
  }

  const Derivatives d = derivatives(segment_of_parameter(u), u);
  const Point2 tangent = (Scalar(1) / norm(d.d1)) * d.d1;
  const Point2 e = p - d.p;
  const Scalar along = dot(e, tangent);
  if (u <= u_min && along < Scalar(0)) {
    const Point2 t0{std::cos(start_.heading), std::sin(start_.heading)};
    const Point2 e0 = p - start_.position;
    return {dot(e0, t0), cross(t0, e0)};
  }
  if (u >= u_max && along > Scalar(0)) {
    const Point2 t1{std::cos(end_.heading), std::sin(end_.heading)};
    const Point2 e1 = p - end_.position;
    return {length_ + dot(e1, t1), cross(t1, e1)};
  }
  return {arc_length_at(u), cross(tangent, e)};
}

Point2 ReferenceLine::to_cartesian(FrenetPoint f) const {
  ITP_EXPECTS(valid_);
  const CurveSample c = evaluate(f.s);
  return c.position + f.l * Point2{-std::sin(c.heading), std::cos(c.heading)};
}

}  // namespace itp::geometry
