// ReferenceLine construction and evaluation along s. The conversions between
// Cartesian and Frenet coordinates are in reference_line_frenet.cpp.
#include "itp/geometry/reference_line.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "itp/configurations.hpp"
#include "itp/geometry/angle.hpp"
#include "reference_line_spline.hpp"

namespace itp::geometry {
namespace {

// Bisection over at most kMaxReferenceKnots entries needs this many halvings.
template <class Cfg>
constexpr int kSearchSteps =
    static_cast<int>(std::bit_width(static_cast<unsigned>(Cfg::kMaxReferenceKnots))) + 1;

// Signed curvature [1/m] of the circle through three points (0 if collinear).
Scalar menger_curvature(Point2 a, Point2 b, Point2 c) {
  const Scalar den = norm(b - a) * norm(c - b) * norm(c - a);
  return den > Scalar(0) ? Scalar(2) * cross(b - a, c - b) / den : Scalar(0);
}

// Tangent angle [rad] at `end` of the circle through end, next, after, where
// `next` is the neighbour of `end` (direction sign: +1 forwards, -1 backwards).
Scalar end_tangent(Point2 end, Point2 next, Scalar kappa) {
  const Point2 chord = next - end;
  const Scalar half_angle =
      std::asin(std::clamp(kappa * norm(chord) / Scalar(2), Scalar(-1), Scalar(1)));
  return std::atan2(chord.y, chord.x) - half_angle;
}

// Mirror image of `p` about the line through `origin` normal to `tangent`.
Point2 mirror_about_normal(Point2 origin, Point2 tangent, Point2 p) {
  const Point2 v = p - origin;
  return origin + (v - (Scalar(2) * dot(v, tangent)) * tangent);
}

}  // namespace

template <class Cfg>
ReferenceLineStatus BasicReferenceLine<Cfg>::build(std::span<const Point2> polyline,
                                                   BasicSmoothingSplineWorkspace<Cfg>& ws) {
  valid_ = false;
  const ReferenceLineStatus check = check_reference_polyline<Cfg>(polyline);
  if (check != ReferenceLineStatus::kOk) {
    return check;
  }
  const int n = static_cast<int>(polyline.size());
  const auto pt = [&](int i) { return polyline[static_cast<std::size_t>(i)]; };
  // Mirror as many points as needed to cover kReferenceMirrorLength (never
  // more than the polyline has, nor kReferenceEndMirror).
  int mirror_front = 1;
  int mirror_back = 1;
  for (int k = 1; k < config::kReferenceEndMirror && k < n - 1; ++k) {
    if (norm(pt(k) - pt(0)) < config::kReferenceMirrorLength) {
      mirror_front = k + 1;
    }
    if (norm(pt(n - 1 - k) - pt(n - 1)) < config::kReferenceMirrorLength) {
      mirror_back = k + 1;
    }
  }

  // End tangents from the circle through the three end points (a straight
  // line for two points), so mirroring preserves the end curvature.
  const Scalar kappa_front = n >= 3 ? menger_curvature(pt(0), pt(1), pt(2)) : Scalar(0);
  const Scalar kappa_back = n >= 3 ? menger_curvature(pt(n - 3), pt(n - 2), pt(n - 1)) : Scalar(0);
  const Scalar theta_front = end_tangent(pt(0), pt(1), kappa_front);
  // Backwards along the curve the signed curvature flips sign.
  const Scalar theta_back = end_tangent(pt(n - 1), pt(n - 2), -kappa_back) + kPi;
  const Point2 tangent_front{std::cos(theta_front), std::sin(theta_front)};
  const Point2 tangent_back{std::cos(theta_back), std::sin(theta_back)};

  // Knots: mirrored front points, the polyline, mirrored back points.
  knots_ = 0;
  for (int k = mirror_front; k >= 1 && k <= config::kReferenceEndMirror; --k) {
    const Point2 q = mirror_about_normal(pt(0), tangent_front, pt(k));
    x_[knots_] = q.x;
    y_[knots_] = q.y;
    ++knots_;
  }
  first_ = knots_;
  for (int i = 0; i < Cfg::kMaxReferencePoints && i < n; ++i) {
    x_[knots_] = pt(i).x;
    y_[knots_] = pt(i).y;
    ++knots_;
  }
  last_ = knots_ - 1;
  for (int k = 1; k <= mirror_back && k <= config::kReferenceEndMirror; ++k) {
    const Point2 q = mirror_about_normal(pt(n - 1), tangent_back, pt(n - 1 - k));
    x_[knots_] = q.x;
    y_[knots_] = q.y;
    ++knots_;
  }

  // Chord-length parameter and the data weights w_i = half the neighbouring
  // chords (so the smoothing does not depend on the sampling density). The
  // weights live in s_ until the arc lengths overwrite them.
  t_[0] = Scalar(0);
  for (int i = 1; i < Cfg::kMaxReferenceKnots && i < knots_; ++i) {
    t_[i] = t_[i - 1] + norm(Point2{x_[i] - x_[i - 1], y_[i] - y_[i - 1]});
  }
  for (int i = 0; i < Cfg::kMaxReferenceKnots && i < knots_; ++i) {
    const Scalar left = i > 0 ? t_[i] - t_[i - 1] : Scalar(0);
    const Scalar right = i + 1 < knots_ ? t_[i + 1] - t_[i] : Scalar(0);
    s_[i] = (left + right) / Scalar(2);
  }

  const auto count = static_cast<std::size_t>(knots_);
  const std::span<const Scalar> t{t_, count};
  const std::span<const Scalar> w{s_, count};
  // g may alias y: the fit reads y_i only before writing g_i.
  if (!fit_smoothing_spline(t, w, std::span<const Scalar>{x_, count}, config::kReferenceSmoothing,
                            ws, std::span<Scalar>{x_, count}, std::span<Scalar>{xpp_, count}) ||
      !fit_smoothing_spline(t, w, std::span<const Scalar>{y_, count}, config::kReferenceSmoothing,
                            ws, std::span<Scalar>{y_, count}, std::span<Scalar>{ypp_, count})) {
    return ReferenceLineStatus::kFitFailed;
  }

  // Arc length at the knots, s = 0 at the first polyline point.
  s_[first_] = Scalar(0);
  for (int i = first_ + 1; i < Cfg::kMaxReferenceKnots && i < knots_; ++i) {
    s_[i] = s_[i - 1] + arc_length_in_segment(i - 1, t_[i]);
  }
  for (int k = 1; k <= config::kReferenceEndMirror && k <= first_; ++k) {
    const int i = first_ - k;
    s_[i] = s_[i + 1] - arc_length_in_segment(i, t_[i + 1]);
  }
  length_ = s_[last_];
  if (!std::isfinite(length_) || length_ < config::kMinReferenceLineLength) {
    return ReferenceLineStatus::kFitFailed;
  }
  valid_ = true;
  start_ = evaluate(Scalar(0));
  end_ = evaluate(length_);
  start_tangent_ = {std::cos(start_.heading), std::sin(start_.heading)};
  end_tangent_ = {std::cos(end_.heading), std::sin(end_.heading)};

  // Bounding circles of the chord groups for the projection's coarse search.
  // A chord lies in the convex hull of its end knots, so a circle holding a
  // group's knots holds its chords. The radius is grown to cover the
  // rounding of the circle test and of the chord distances in to_frenet()
  // (a few eps of the coordinates; 64 eps is generous).
  const Scalar eps = std::numeric_limits<Scalar>::epsilon();
  groups_ = (last_ - first_ + kChordGroup - 1) / kChordGroup;
  for (int g = 0; g < kMaxChordGroups && g < groups_; ++g) {
    const int k0 = first_ + g * kChordGroup;
    const int k1 = std::min(k0 + kChordGroup, last_);
    Point2 lo{x_[k0], y_[k0]};
    Point2 hi = lo;
    for (int k = k0 + 1; k <= k1 && k - k0 <= kChordGroup; ++k) {  // kChordGroup
      lo = {std::min(lo.x, x_[k]), std::min(lo.y, y_[k])};
      hi = {std::max(hi.x, x_[k]), std::max(hi.y, y_[k])};
    }
    const Point2 centre = Scalar(0.5) * (lo + hi);
    Scalar radius = Scalar(0);
    for (int k = k0; k <= k1 && k - k0 <= kChordGroup; ++k) {  // kChordGroup + 1
      radius = std::max(radius, norm(Point2{x_[k], y_[k]} - centre));
    }
    group_centre_[g] = centre;
    group_radius_[g] =
        radius + Scalar(64) * eps * (Scalar(1) + radius + std::fabs(centre.x) + std::fabs(centre.y));
  }
  return ReferenceLineStatus::kOk;
}

// u(s): bisection over the knots' arc lengths, then Newton on
// f(w) = (s_lo - s) + s(w) with f'(w) = |C'(w)|, w = u - t_lo, started from
// linear interpolation. s_lo - s is exact (or nearly so), so f is accurate to
// ~eps times the segment length, not eps |s|. Newton stops when |f| is at
// rounding level, or when the step is so small that the next one would be:
// its error in s is at most step^2 max|C''| / 2 (quadratic convergence;
// f'' = C'.C''/|C'| <= |C''|, whose maximum on the segment is at a knot since
// C'' is linear). Typically one arc-length integral per call (1.2 to 1.4 on
// the test roads), against kArcLengthNewtonSteps (4) plus 4 speeds before.
template <class Cfg>
Scalar BasicReferenceLine<Cfg>::parameter_at(Scalar s, int& segment) const {
  int lo = first_;
  int hi = last_;
  for (int step = 0; step < kSearchSteps<Cfg> && hi - lo > 1; ++step) {
    const int mid = (lo + hi) / 2;
    if (s_[mid] <= s) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  segment = lo;
  const Tangent q = tangent_polynomial(lo);
  const Scalar h = t_[lo + 1] - t_[lo];
  const Scalar seg_s = s_[lo + 1] - s_[lo];
  Scalar w = (s - s_[lo]) / seg_s * h;
  const Point2 d2_end{xpp_[lo + 1], ypp_[lo + 1]};  // C'' at the segment's end (q.b at its start)
  const Scalar max_d2_sq = std::max(dot(q.b, q.b), dot(d2_end, d2_end));
  const Scalar tolerance =
      std::numeric_limits<Scalar>::epsilon() * (Scalar(1) + std::fabs(s)) / Scalar(2);
  for (int it = 0; it < config::kArcLengthNewtonSteps; ++it) {  // kArcLengthNewtonSteps
    const Scalar f = (s_[lo] - s) + spline_detail::arc_length_of(q.a, q.b, q.c, w);
    if (std::fabs(f) <= tolerance) {
      break;
    }
    const Scalar speed = norm(spline_detail::tangent_at(q.a, q.b, q.c, w));
    const Scalar step = f / speed;
    w = std::clamp(w - step, Scalar(0), h);
    // Stop if the next error, step^2 max|C''| / 2 in s, is <= tolerance / 2.
    const Scalar step2 = step * step;
    if (step2 * step2 * max_d2_sq <= tolerance * tolerance) {
      break;
    }
  }
  return std::clamp(t_[lo] + w, t_[lo], t_[lo + 1]);
}

template <class Cfg>
CurveSample BasicReferenceLine<Cfg>::sample_of(const Derivatives& d) {
  const Scalar speed2 = dot(d.d1, d.d1);
  const Scalar speed = std::sqrt(speed2);
  const Scalar c12 = cross(d.d1, d.d2);
  CurveSample out;
  out.position = d.p;
  out.heading = std::atan2(d.d1.y, d.d1.x);
  // kappa = (x'y'' - y'x'') / |C'|^3, and its derivative in u divided by |C'|.
  out.kappa = c12 / (speed2 * speed);
  const Scalar dkappa_du =
      (cross(d.d1, d.d3) * speed2 - Scalar(3) * c12 * dot(d.d1, d.d2)) / (speed2 * speed2 * speed);
  out.dkappa = dkappa_du / speed;
  return out;
}

template <class Cfg>
CurveSample BasicReferenceLine<Cfg>::evaluate(Scalar s) const {
  if (s < Scalar(0) || s > length_) {
    const CurveSample& end = s < Scalar(0) ? start_ : end_;
    const Point2 tangent = s < Scalar(0) ? start_tangent_ : end_tangent_;
    const Scalar ds = s < Scalar(0) ? s : s - length_;
    CurveSample out;
    out.position = end.position + ds * tangent;
    out.heading = end.heading;
    return out;  // straight extension: kappa = dkappa = 0
  }
  int segment = 0;
  const Scalar u = parameter_at(s, segment);
  return sample_of(derivatives(segment_near(segment, u), u));
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C) template class BasicReferenceLine<C>;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::geometry
