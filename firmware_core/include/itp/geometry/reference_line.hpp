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

template <class Cfg>
class BasicReferenceLine {
 public:
  // Builds from the polyline [m] (driving order). On failure the line stays
  // invalid (valid() == false) and the reason is returned. No allocation;
  // `ws` is scratch for the fit.
  ReferenceLineStatus build(std::span<const Point2> polyline,
                            BasicSmoothingSplineWorkspace<Cfg>& ws);

  bool valid() const { return valid_; }
  Scalar length() const { return length_; }  // [m] arc length of the smoothed curve

  // Curve at arc length s [m]; straight extension outside [0, length()].
  CurveSample evaluate(Scalar s) const;

  // Cartesian -> Frenet: the foot point on the smoothed curve nearest to p
  // (coarse search for the nearest knot chord, pruned by bounding circles of
  // chord groups, then Newton on the spline).
  FrenetPoint to_frenet(Point2 p) const;
  // The same projection (bit for bit the same s and l), and the reference
  // curve at the foot point in `foot`, i.e. evaluate(s) without inverting s
  // again: equal to evaluate(s) up to rounding (position ~3e-14 m, heading
  // ~1e-15 rad with double). Beyond the ends `foot` is the straight
  // extension (kappa = dkappa = 0), as in evaluate(s).
  FrenetPoint to_frenet(Point2 p, CurveSample& foot) const;
  // Frenet -> Cartesian: position(s) + l * normal(s).
  Point2 to_cartesian(FrenetPoint f) const;

 private:
  struct Derivatives {
    Point2 p;    // C(u)      [m]
    Point2 d1;   // C'(u)     [-]
    Point2 d2;   // C''(u)    [1/m]
    Point2 d3;   // C'''(u)   [1/m^2]
  };
  // C'(t_i + w) = a + b w + c w^2 on segment i, w in [0, h_i]: the
  // derivative of the cubic in derivatives(), expanded in powers of w.
  struct Tangent {
    Point2 a;    // [-]
    Point2 b;    // [1/m]
    Point2 c;    // [1/m^2]
  };

  // The spline kernels (inline, defined in src/geometry/reference_line_spline.hpp).
  // The knot interval [i, i+1] holding u: the largest i <= knots_ - 2 with
  // t_[i] <= u (0 if none), found by walking from `hint`.
  inline int segment_near(int hint, Scalar u) const;
  inline Derivatives derivatives(int segment, Scalar u) const;
  inline Tangent tangent_polynomial(int segment) const;
  inline Scalar arc_length_in_segment(int segment, Scalar u) const;  // [m] from t_[segment] to u
  Scalar parameter_at(Scalar s, int& segment) const;  // u(s), s in [0, length_]; its interval
  // Index of the real chord [i, i+1] nearest to p, and the position tau in
  // [0, 1] along it of p's nearest point (the first such chord on ties).
  int nearest_chord(Point2 p, Scalar& tau) const;
  void scan_chords(Point2 p, int group, int& best, Scalar& best_tau, Scalar& best_d2) const;
  FrenetPoint project(Point2 p, CurveSample* foot) const;
  static CurveSample sample_of(const Derivatives& d);  // heading, kappa, dkappa at C(u)

  // The coarse projection search visits the real chords in groups of
  // kChordGroup consecutive chords, each with a bounding circle.
  static constexpr int kChordGroup = 8;
  static constexpr int kMaxChordGroups =
      (Cfg::kMaxReferencePoints - 1 + kChordGroup - 1) / kChordGroup;

  // Spline data: knots = mirrored points + polyline + mirrored points.
  Scalar t_[Cfg::kMaxReferenceKnots] = {};    // [m] chord-length parameter
  Scalar x_[Cfg::kMaxReferenceKnots] = {};    // [m] fitted x at knots
  Scalar y_[Cfg::kMaxReferenceKnots] = {};    // [m] fitted y at knots
  Scalar xpp_[Cfg::kMaxReferenceKnots] = {};  // [1/m] d2x/du2 at knots
  Scalar ypp_[Cfg::kMaxReferenceKnots] = {};  // [1/m] d2y/du2 at knots
  Scalar s_[Cfg::kMaxReferenceKnots] = {};    // [m] arc length at knots, s_[first_] = 0
  int knots_ = 0;
  int first_ = 0;  // knot of the first polyline point
  int last_ = 0;   // knot of the last polyline point
  Scalar length_ = Scalar(0);  // [m]
  CurveSample start_;          // curve at s = 0
  CurveSample end_;            // curve at s = length_
  Point2 start_tangent_;       // (cos, sin) of start_.heading
  Point2 end_tangent_;         // (cos, sin) of end_.heading
  // Chord groups: group g holds the real chords first_ + g kChordGroup ...
  // (at most kChordGroup of them, ending at last_); every point of those
  // chords is within group_radius_[g] of group_centre_[g], with a margin for
  // rounding (see build()).
  Point2 group_centre_[std::size_t{kMaxChordGroups}] = {};  // [m]
  Scalar group_radius_[std::size_t{kMaxChordGroups}] = {};  // [m]
  int groups_ = 0;
  bool valid_ = false;
};

using ReferenceLine = BasicReferenceLine<DefaultConfig>;

}  // namespace itp::geometry
