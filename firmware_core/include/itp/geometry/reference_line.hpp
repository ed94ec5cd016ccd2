#pragma once
// The reference line: a smooth, arc-length parameterised curve built from the
// lane-centre polyline, and the Frenet frame (s, l) it defines.
//
// Curve: a natural cubic smoothing spline x(u), y(u) over the cumulative
// chord length u of the polyline, with kReferenceEndMirror points mirrored
// about the normal at each end so the natural end condition does not flatten
// the curvature at the real ends (docs/frenet.md). s is the true arc length of
// that spline (Gauss-Legendre), s = 0 at the first polyline point. Every
// quantity here (s, l, heading, kappa) refers to the smoothed curve, in both
// conversion directions. Beyond [0, length()] the frame continues along the
// end tangents as straight lines (kappa = 0 there).
#include <span>

#include "itp/config.hpp"
#include "itp/geometry/point.hpp"
#include "itp/geometry/reference_polyline.hpp"
#include "itp/geometry/smoothing_spline.hpp"

namespace itp::geometry {

// The reference curve at one arc length.
struct CurveSample {
  Point2 position;                // [m]
  Scalar heading = Scalar(0);     // [rad] tangent direction, in (-pi, pi]
  Scalar kappa = Scalar(0);       // [1/m] signed curvature, > 0 turning left
  Scalar dkappa = Scalar(0);      // [1/m^2] d kappa / ds
};

class ReferenceLine {
 public:
  // Builds from the polyline [m] (driving order). On failure the line stays
  // invalid (valid() == false) and the reason is returned. No allocation;
  // `ws` is scratch for the fit.
  ReferenceLineStatus build(std::span<const Point2> polyline, SmoothingSplineWorkspace& ws);

  bool valid() const { return valid_; }
  Scalar length() const { return length_; }  // [m] arc length of the smoothed curve

  // Curve at arc length s [m]; straight extension outside [0, length()].
  CurveSample evaluate(Scalar s) const;

  // Cartesian -> Frenet: the foot point on the smoothed curve nearest to p
  // (coarse search over the knot chords, then Newton on the spline).
  FrenetPoint to_frenet(Point2 p) const;
  // Frenet -> Cartesian: position(s) + l * normal(s).
  Point2 to_cartesian(FrenetPoint f) const;

 private:
  struct Derivatives {
    Point2 p;    // C(u)      [m]
    Point2 d1;   // C'(u)     [-]
    Point2 d2;   // C''(u)    [1/m]
    Point2 d3;   // C'''(u)   [1/m^2]
  };

  int segment_of_parameter(Scalar u) const;  // knot interval [i, i+1] holding u
  Derivatives derivatives(int segment, Scalar u) const;
  Scalar arc_length_in_segment(int segment, Scalar u) const;  // [m] from t_[segment] to u
  Scalar parameter_at(Scalar s) const;        // u(s), s in [0, length_]
  Scalar arc_length_at(Scalar u) const;       // s(u), u in [t_[first_], t_[last_]]

  // Spline data: knots = mirrored points + polyline + mirrored points.
  Scalar t_[config::kMaxReferenceKnots] = {};    // [m] chord-length parameter
  Scalar x_[config::kMaxReferenceKnots] = {};    // [m] fitted x at knots
  Scalar y_[config::kMaxReferenceKnots] = {};    // [m] fitted y at knots
  Scalar xpp_[config::kMaxReferenceKnots] = {};  // [1/m] d2x/du2 at knots
  Scalar ypp_[config::kMaxReferenceKnots] = {};  // [1/m] d2y/du2 at knots
  Scalar s_[config::kMaxReferenceKnots] = {};    // [m] arc length at knots, s_[first_] = 0
  int knots_ = 0;
  int first_ = 0;  // knot of the first polyline point
  int last_ = 0;   // knot of the last polyline point
  Scalar length_ = Scalar(0);  // [m]
  CurveSample start_;          // curve at s = 0
  CurveSample end_;            // curve at s = length_
  bool valid_ = false;
};

}  // namespace itp::geometry
