// ReferenceLine construction and evaluation along s. The conversions between
// Cartesian and Frenet coordinates are in reference_line_frenet.cpp.
#include "itp/geometry/reference_line.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "itp/geometry/angle.hpp"

namespace itp::geometry {
namespace {

// Bisection over at most kMaxReferenceKnots entries needs this many halvings.
constexpr int kSearchSteps =
    static_cast<int>(std::bit_width(static_cast<unsigned>(config::kMaxReferenceKnots))) + 1;

// 5-point Gauss-Legendre on [-1, 1]: exact for polynomials of degree 9; the
// speed |C'(u)| is a smooth function close to 1 on each segment.
constexpr int kGaussPoints = 5;
constexpr Scalar kGaussNode[kGaussPoints] = {
    Scalar(-0.9061798459386640), Scalar(-0.5384693101056831), Scalar(0),
    Scalar(0.5384693101056831), Scalar(0.9061798459386640)};
constexpr Scalar kGaussWeight[kGaussPoints] = {
    Scalar(0.2369268850561891), Scalar(0.4786286704993665), Scalar(0.5688888888888889),
    Scalar(0.4786286704993665), Scalar(0.2369268850561891)};

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

ReferenceLineStatus ReferenceLine::build(std::span<const Point2> polyline,
                                         SmoothingSplineWorkspace& ws) {
  valid_ = false;
  const ReferenceLineStatus check = check_reference_polyline(polyline);
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
  for (int i = 0; i < config::kMaxReferencePoints && i < n; ++i) {
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
  for (int i = 1; i < config::kMaxReferenceKnots && i < knots_; ++i) {
    t_[i] = t_[i - 1] + norm(Point2{x_[i] - x_[i - 1], y_[i] - y_[i - 1]});
  }
  for (int i = 0; i < config::kMaxReferenceKnots && i < knots_; ++i) {
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
  for (int i = first_ + 1; i < config::kMaxReferenceKnots && i < knots_; ++i) {
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
  return ReferenceLineStatus::kOk;
}

int ReferenceLine::segment_of_parameter(Scalar u) const {
  int lo = 0;
  int hi = knots_ - 1;
  for (int step = 0; step < kSearchSteps && hi - lo > 1; ++step) {
    const int mid = (lo + hi) / 2;
    if (t_[mid] <= u) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

// Cubic on [t_i, t_{i+1}], h = t_{i+1} - t_i, a = (t_{i+1} - u)/h, b = 1 - a:
//   x   = a x_i + b x_{i+1} + ((a^3 - a) x''_i + (b^3 - b) x''_{i+1}) h^2 / 6
//   x'  = (x_{i+1} - x_i)/h - (3a^2 - 1) h x''_i / 6 + (3b^2 - 1) h x''_{i+1} / 6
//   x'' = a x''_i + b x''_{i+1},   x''' = (x''_{i+1} - x''_i) / h
ReferenceLine::Derivatives ReferenceLine::derivatives(int i, Scalar u) const {
  const Scalar h = t_[i + 1] - t_[i];
  const Scalar a = (t_[i + 1] - u) / h;
  const Scalar b = (u - t_[i]) / h;
  const Scalar h2_6 = h * h / Scalar(6);
  const Scalar ca = (a * a * a - a) * h2_6;
  const Scalar cb = (b * b * b - b) * h2_6;
  const Scalar da = (Scalar(3) * a * a - Scalar(1)) * h / Scalar(6);
  const Scalar db = (Scalar(3) * b * b - Scalar(1)) * h / Scalar(6);
  Derivatives d;
  d.p = {a * x_[i] + b * x_[i + 1] + ca * xpp_[i] + cb * xpp_[i + 1],
         a * y_[i] + b * y_[i + 1] + ca * ypp_[i] + cb * ypp_[i + 1]};
  d.d1 = {(x_[i + 1] - x_[i]) / h - da * xpp_[i] + db * xpp_[i + 1],
          (y_[i + 1] - y_[i]) / h - da * ypp_[i] + db * ypp_[i + 1]};
  d.d2 = {a * xpp_[i] + b * xpp_[i + 1], a * ypp_[i] + b * ypp_[i + 1]};
  d.d3 = {(xpp_[i + 1] - xpp_[i]) / h, (ypp_[i + 1] - ypp_[i]) / h};
  return d;
}

Scalar ReferenceLine::arc_length_in_segment(int i, Scalar u) const {
  const Scalar half = (u - t_[i]) / Scalar(2);
  const Scalar mid = t_[i] + half;
  Scalar sum = Scalar(0);
  for (int g = 0; g < kGaussPoints; ++g) {
    sum += kGaussWeight[g] * norm(derivatives(i, mid + half * kGaussNode[g]).d1);
  }
  return half * sum;
}

Scalar ReferenceLine::arc_length_at(Scalar u) const {
  const int i = segment_of_parameter(u);
  return s_[i] + arc_length_in_segment(i, u);
}

// u(s): bisection over the knots' arc lengths, then Newton on
// f(u) = s(u) - s with f'(u) = |C'(u)|, started from linear interpolation.
Scalar ReferenceLine::parameter_at(Scalar s) const {
  int lo = first_;
  int hi = last_;
  for (int step = 0; step < kSearchSteps && hi - lo > 1; ++step) {
    const int mid = (lo + hi) / 2;
    if (s_[mid] <= s) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  const Scalar seg_s = s_[lo + 1] - s_[lo];
  Scalar u = t_[lo] + (s - s_[lo]) / seg_s * (t_[lo + 1] - t_[lo]);
  for (int it = 0; it < config::kArcLengthNewtonSteps; ++it) {
    const Scalar f = s_[lo] + arc_length_in_segment(lo, u) - s;
    const Scalar speed = norm(derivatives(lo, u).d1);
    u = std::clamp(u - f / speed, t_[lo], t_[lo + 1]);
  }
  return u;
}

CurveSample ReferenceLine::evaluate(Scalar s) const {
  if (s < Scalar(0) || s > length_) {
    const CurveSample& end = s < Scalar(0) ? start_ : end_;
    const Scalar ds = s < Scalar(0) ? s : s - length_;
    CurveSample out;
    out.position = end.position + ds * Point2{std::cos(end.heading), std::sin(end.heading)};
    out.heading = end.heading;
    return out;  // straight extension: kappa = dkappa = 0
  }
  const Scalar u = parameter_at(s);
  const Derivatives d = derivatives(segment_of_parameter(u), u);
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

}  // namespace itp::geometry
