#pragma once
// Private to src/geometry: the spline evaluation kernels of ReferenceLine,
// inline so that reference_line.cpp (build, evaluate) and
// reference_line_frenet.cpp (projection) both inline them. Not a public header.
#include <algorithm>

#include "itp/geometry/reference_line.hpp"

namespace itp::geometry {
namespace spline_detail {

// 5-point Gauss-Legendre on [-1, 1]: exact for polynomials of degree 9; the
// speed |C'(u)| is a smooth function close to 1 on each segment.
inline constexpr int kGaussPoints = 5;
inline constexpr Scalar kGaussNode[kGaussPoints] = {
    Scalar(-0.9061798459386640), Scalar(-0.5384693101056831), Scalar(0),
    Scalar(0.5384693101056831), Scalar(0.9061798459386640)};
inline constexpr Scalar kGaussWeight[kGaussPoints] = {
    Scalar(0.2369268850561891), Scalar(0.4786286704993665), Scalar(0.5688888888888889),
    Scalar(0.4786286704993665), Scalar(0.2369268850561891)};

// C' = a + b w + c w^2 at w.
inline Point2 tangent_at(Point2 a, Point2 b, Point2 c, Scalar w) { return a + w * (b + w * c); }

// Arc length [m] from w = 0 to w of the curve with C' = a + b w + c w^2.
inline Scalar arc_length_of(Point2 a, Point2 b, Point2 c, Scalar w) {
  const Scalar half = w / Scalar(2);
  Scalar sum = Scalar(0);
  for (int g = 0; g < kGaussPoints; ++g) {  // kGaussPoints
    sum += kGaussWeight[g] * norm(tangent_at(a, b, c, half + half * kGaussNode[g]));
  }
  return half * sum;
}

}  // namespace spline_detail

// The same interval as a bisection over all knots would find; the callers'
// hints are at most a knot or two away. Each walk: <= kMaxReferenceKnots steps.
template <class Cfg>
inline int BasicReferenceLine<Cfg>::segment_near(int hint, Scalar u) const {
  int i = std::clamp(hint, 0, knots_ - 2);
  for (int step = 0; step < Cfg::kMaxReferenceKnots && i > 0 && t_[i] > u; ++step) {
    --i;
  }
  for (int step = 0; step < Cfg::kMaxReferenceKnots && i < knots_ - 2 && t_[i + 1] <= u; ++step) {
    ++i;
  }
  return i;
}

// Cubic on [t_i, t_{i+1}], h = t_{i+1} - t_i, a = (t_{i+1} - u)/h, b = (u - t_i)/h:
//   x   = x_i + b (x_{i+1} - x_i) + ((a^3 - a) x''_i + (b^3 - b) x''_{i+1}) h^2 / 6
//         (a x_i + b x_{i+1} with a + b = 1, written so a + b != 1 in rounding
//         costs no eps |x| of position noise)
//   x'  = (x_{i+1} - x_i)/h - (3a^2 - 1) h x''_i / 6 + (3b^2 - 1) h x''_{i+1} / 6
//   x'' = a x''_i + b x''_{i+1},   x''' = (x''_{i+1} - x''_i) / h
template <class Cfg>
inline typename BasicReferenceLine<Cfg>::Derivatives BasicReferenceLine<Cfg>::derivatives(
    int i, Scalar u) const {
  const Scalar h = t_[i + 1] - t_[i];
  const Scalar inv_h = Scalar(1) / h;
  const Scalar a = (t_[i + 1] - u) * inv_h;
  const Scalar b = (u - t_[i]) * inv_h;
  const Scalar h_6 = h * (Scalar(1) / Scalar(6));
  const Scalar h2_6 = h * h_6;
  const Scalar ca = (a * a * a - a) * h2_6;
  const Scalar cb = (b * b * b - b) * h2_6;
  const Scalar da = (Scalar(3) * a * a - Scalar(1)) * h_6;
  const Scalar db = (Scalar(3) * b * b - Scalar(1)) * h_6;
  const Scalar dx = x_[i + 1] - x_[i];
  const Scalar dy = y_[i + 1] - y_[i];
  Derivatives d;
  d.p = {x_[i] + b * dx + (ca * xpp_[i] + cb * xpp_[i + 1]),
         y_[i] + b * dy + (ca * ypp_[i] + cb * ypp_[i + 1])};
  d.d1 = {dx * inv_h - da * xpp_[i] + db * xpp_[i + 1], dy * inv_h - da * ypp_[i] + db * ypp_[i + 1]};
  d.d2 = {a * xpp_[i] + b * xpp_[i + 1], a * ypp_[i] + b * ypp_[i + 1]};
  d.d3 = {(xpp_[i + 1] - xpp_[i]) * inv_h, (ypp_[i + 1] - ypp_[i]) * inv_h};
  return d;
}

// x'(t_i + w) = (x_{i+1} - x_i)/h - (2 x''_i + x''_{i+1}) h/6 + x''_i w
//                + (x''_{i+1} - x''_i)/(2h) w^2   (the same for y).
template <class Cfg>
inline typename BasicReferenceLine<Cfg>::Tangent BasicReferenceLine<Cfg>::tangent_polynomial(
    int i) const {
  const Scalar h = t_[i + 1] - t_[i];
  const Scalar inv_h = Scalar(1) / h;
  const Scalar h_6 = h * (Scalar(1) / Scalar(6));
  Tangent q;
  q.a = {(x_[i + 1] - x_[i]) * inv_h - (Scalar(2) * xpp_[i] + xpp_[i + 1]) * h_6,
         (y_[i + 1] - y_[i]) * inv_h - (Scalar(2) * ypp_[i] + ypp_[i + 1]) * h_6};
  q.b = {xpp_[i], ypp_[i]};
  const Scalar half_inv_h = Scalar(0.5) * inv_h;
  q.c = {(xpp_[i + 1] - xpp_[i]) * half_inv_h, (ypp_[i + 1] - ypp_[i]) * half_inv_h};
  return q;
}

template <class Cfg>
inline Scalar BasicReferenceLine<Cfg>::arc_length_in_segment(int i, Scalar u) const {
  const Tangent q = tangent_polynomial(i);
  return spline_detail::arc_length_of(q.a, q.b, q.c, u - t_[i]);
}

}  // namespace itp::geometry
