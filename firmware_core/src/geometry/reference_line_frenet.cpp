// Cartesian <-> Frenet conversion on the smoothed reference curve.
#include <algorithm>
#include <cmath>
#include <limits>

#include "itp/configurations.hpp"
#include "itp/core/assert.hpp"
#include "itp/geometry/reference_line.hpp"
#include "reference_line_spline.hpp"

namespace itp::geometry {

// Distance^2 from p to the chords of one group, folded into the running best
// (smaller distance wins; on equal distances the lower chord index wins, as
// in a scan of all chords in order).
template <class Cfg>
void BasicReferenceLine<Cfg>::scan_chords(Point2 p, int group, int& best, Scalar& best_tau,
                                          Scalar& best_d2) const {
  const int k0 = first_ + group * kChordGroup;
  const int k1 = std::min(k0 + kChordGroup, last_);
  for (int i = k0; i < k1 && i - k0 < kChordGroup; ++i) {  // kChordGroup
    const Point2 a{x_[i], y_[i]};
    const Point2 d{x_[i + 1] - x_[i], y_[i + 1] - y_[i]};
    const Scalar tau = std::clamp(dot(p - a, d) / dot(d, d), Scalar(0), Scalar(1));
    const Point2 e = p - (a + tau * d);
    const Scalar d2 = dot(e, e);
    if (d2 < best_d2 || (d2 == best_d2 && i < best)) {
      best_d2 = d2;
      best = i;
      best_tau = tau;
    }
  }
}

// The nearest real chord, exactly as a scan of all chords in order finds it
// (same distance formula, same tie rule), but visiting only the groups whose
// bounding circle can hold a chord at least as near as the best one so far.
// The group with the nearest centre goes first. Group g is skipped when
//   |p - centre_g| > radius_g + m + sqrt(best_d2 (1 + 8 eps)),
// compared squared, where m = 64 eps (|p.x| + |p.y|) covers the rounding that
// grows with p (the stored radius covers the rest, see build()): every chord
// distance^2 that the full scan would compute in that group is then
// > best_d2, so none of them could win or tie.
template <class Cfg>
int BasicReferenceLine<Cfg>::nearest_chord(Point2 p, Scalar& tau) const {
  const Scalar eps = std::numeric_limits<Scalar>::epsilon();
  const Scalar margin = Scalar(64) * eps * (std::fabs(p.x) + std::fabs(p.y));
  Scalar centre_d2[std::size_t{kMaxChordGroups}] = {};  // |p - centre|^2 [m^2]
  int start = 0;
  for (int g = 0; g < kMaxChordGroups && g < groups_; ++g) {  // kMaxChordGroups
    const Point2 v = p - group_centre_[g];
    centre_d2[g] = dot(v, v);
    if (centre_d2[g] < centre_d2[start]) {
      start = g;
    }
  }
  int best = first_;
  Scalar best_tau = Scalar(0);
  Scalar best_d2 = std::numeric_limits<Scalar>::max();
  scan_chords(p, start, best, best_tau, best_d2);
  Scalar reach = margin + std::sqrt(best_d2 * (Scalar(1) + Scalar(8) * eps));
  for (int g = 0; g < kMaxChordGroups && g < groups_; ++g) {  // kMaxChordGroups
    const Scalar r = group_radius_[g] + reach;
    if (g != start && !(centre_d2[g] > r * r)) {
      const Scalar before = best_d2;
      scan_chords(p, g, best, best_tau, best_d2);
      if (best_d2 < before) {
        reach = margin + std::sqrt(best_d2 * (Scalar(1) + Scalar(8) * eps));
      }
    }
  }
  tau = best_tau;
  return best;
}

// Foot point of p on the curve C(u), u in [t_first, t_last]:
//  1. coarse: the nearest chord between consecutive knots (all real segments,
//     at most kMaxReferencePoints - 1, pruned by nearest_chord()), giving u0;
//  2. Newton on g(u) = (C(u) - p) . C'(u) = 0, g'(u) = |C'|^2 + (C - p) . C''
//     (at most kProjectionNewtonSteps; |l| < 1/|kappa| keeps g' > 0, else the
//     step falls back to Gauss-Newton), clamped to the curve's ends.
// Then s = s(u), l = T x (p - C). A point beyond an end is expressed in the
// straight extension of that end, exactly as to_cartesian extends it.
template <class Cfg>
FrenetPoint BasicReferenceLine<Cfg>::project(Point2 p, CurveSample* foot) const {
  ITP_EXPECTS(valid_);
  Scalar best_tau = Scalar(0);
  int segment = nearest_chord(p, best_tau);
  const Scalar u_min = t_[first_];
  const Scalar u_max = t_[last_];
  Scalar u = t_[segment] + best_tau * (t_[segment + 1] - t_[segment]);
  const Scalar tolerance = Scalar(8) * std::numeric_limits<Scalar>::epsilon() * (Scalar(1) + u_max);
  for (int it = 0; it < config::kProjectionNewtonSteps; ++it) {  // kProjectionNewtonSteps
    segment = segment_near(segment, u);
    const Derivatives d = derivatives(segment, u);
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

  segment = segment_near(segment, u);
  const Derivatives d = derivatives(segment, u);
  const Point2 tangent = (Scalar(1) / norm(d.d1)) * d.d1;
  const Point2 e = p - d.p;
  const Scalar along = dot(e, tangent);
  if ((u <= u_min && along < Scalar(0)) || (u >= u_max && along > Scalar(0))) {
    const bool before = u <= u_min && along < Scalar(0);
    const CurveSample& end = before ? start_ : end_;
    const Point2 t = before ? start_tangent_ : end_tangent_;
    const Point2 e_end = p - end.position;
    const Scalar ds = dot(e_end, t);
    if (foot != nullptr) {
      foot->position = end.position + ds * t;
      foot->heading = end.heading;
      foot->kappa = Scalar(0);
      foot->dkappa = Scalar(0);
    }
    return {before ? ds : length_ + ds, cross(t, e_end)};
  }
  if (foot != nullptr) {
    *foot = sample_of(d);
  }
  return {s_[segment] + arc_length_in_segment(segment, u), cross(tangent, e)};
}

template <class Cfg>
FrenetPoint BasicReferenceLine<Cfg>::to_frenet(Point2 p) const {
  return project(p, nullptr);
}

template <class Cfg>
FrenetPoint BasicReferenceLine<Cfg>::to_frenet(Point2 p, CurveSample& foot) const {
  return project(p, &foot);
}

// position(s) + l * normal(s), with the unit normal taken from C'(u) directly
// (the same direction as (-sin, cos) of evaluate(s).heading).
template <class Cfg>
Point2 BasicReferenceLine<Cfg>::to_cartesian(FrenetPoint f) const {
  ITP_EXPECTS(valid_);
  if (f.s < Scalar(0) || f.s > length_) {
    const bool before = f.s < Scalar(0);
    const CurveSample& end = before ? start_ : end_;
    const Point2 t = before ? start_tangent_ : end_tangent_;
    const Point2 position = end.position + (before ? f.s : f.s - length_) * t;
    return position + f.l * Point2{-t.y, t.x};
  }
  int segment = 0;
  const Scalar u = parameter_at(f.s, segment);
  const Derivatives d = derivatives(segment_near(segment, u), u);
  const Scalar inv_speed = Scalar(1) / norm(d.d1);
  return d.p + f.l * Point2{-d.d1.y * inv_speed, d.d1.x * inv_speed};
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                           \
  template FrenetPoint BasicReferenceLine<C>::to_frenet(Point2) const;               \
  template FrenetPoint BasicReferenceLine<C>::to_frenet(Point2, CurveSample&) const; \
  template Point2 BasicReferenceLine<C>::to_cartesian(FrenetPoint) const;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::geometry
