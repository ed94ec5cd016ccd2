#pragma once
// Frenet-frame helpers built on a ReferenceLine: heading <-> l' conversion and
// the SL bounding rectangle of an oriented box (paper 1.1, "SL block").
#include "itp/geometry/oriented_box.hpp"
#include "itp/geometry/point.hpp"
#include "itp/geometry/reference_line.hpp"
#include "itp/geometry/sl_box.hpp"

namespace itp::geometry {

// l' = dl/ds of a path with world heading `heading` [rad] at lateral offset
// l [m], where the reference has heading `ref_heading` [rad] and curvature
// `ref_kappa` [1/m]:  l' = (1 - kappa_ref l) tan(heading - ref_heading).
// Meaningful for |heading - ref_heading| < pi/2 and kappa_ref l < 1.
Scalar lateral_slope(Scalar heading, Scalar ref_heading, Scalar ref_kappa, Scalar l);

// Inverse of lateral_slope: heading = ref_heading + atan2(l', 1 - kappa_ref l),
// wrapped to (-pi, pi].
Scalar heading_from_lateral_slope(Scalar l_prime, Scalar ref_heading, Scalar ref_kappa,
                                  Scalar l);

// Heading relative to the reference, wrapped to (-pi, pi] [rad].
Scalar relative_heading(Scalar heading, Scalar ref_heading);

// The motion of a point that follows the Frenet path l(s) at s(t), in world
// terms. With the reference's tangent T, left normal N (T' = kappa N,
// N' = -kappa T) and q = 1 - kappa l, the point r = c(s) + l N has
//   dr/ds = q T + l' N,  |dr/ds| = g = sqrt(q^2 + l'^2),
// so v = s' g and a = dv/dt = s'' g + s'^2 g_s with
//   g_s = (q q_s + l' l'') / g,  q_s = -(kappa' l + kappa l'),
// its heading is ref_heading + atan2(l', q), and its curvature
//   kappa_c = (kappa + (q l'' - l' q_s) / g^2) / g.
struct FrenetState {
  Scalar ds = 0;          // [m/s] s' = ds/dt
  Scalar dds = 0;         // [m/s^2] s'' = d2s/dt2
  Scalar l = 0;           // [m]
  Scalar dl = 0;          // [-] l' = dl/ds
  Scalar ddl = 0;         // [1/m] l'' = d2l/ds2
  Scalar ref_kappa = 0;   // [1/m] of the reference at s
  Scalar ref_dkappa = 0;  // [1/m^2] its derivative along s
};

struct CartesianMotion {
  Scalar relative_heading = 0;  // [rad] heading - ref_heading = atan2(l', q)
  Scalar kappa = 0;             // [1/m] curvature of the point's path
  Scalar v = 0;                 // [m/s] speed (s' g, signed as s')
  Scalar a = 0;                 // [m/s^2] dv/dt
  Scalar scale = 1;             // [-] g = |dr/ds|: world distance per metre of s
};

// Meaningful for q = 1 - kappa l > 0 (the point inside the reference's radius).
CartesianMotion cartesian_motion(const FrenetState& f);

// A vehicle's motion in the world frame (its reference point, e.g. the rear axle).
struct CartesianState {
  Point2 position;             // [m]
  Scalar heading = Scalar(0);  // [rad]
  Scalar kappa = Scalar(0);    // [1/m] curvature of its path
  Scalar v = Scalar(0);        // [m/s]
  Scalar a = Scalar(0);        // [m/s^2] dv/dt
};

// Frenet to world at the reference sample `ref` taken at the point's s
// (exact: cartesian_motion, with f's reference curvature taken from ref).
CartesianState to_cartesian(const CurveSample& ref, FrenetState f);

// World to Frenet for a point at lateral offset `l` whose foot point on the
// reference is `ref`: l' from the relative heading dtheta, and with
// q = 1 - kappa_ref l,
//   l'' = (kappa q / cos(dtheta) - kappa_ref) q / cos^2(dtheta)   (kappa_ref' neglected),
//   s'  = v cos(dtheta) / q,
//   s'' = a cos(dtheta) / q                                        (the s'^2 g_s term neglected).
// The result's ref_kappa and ref_dkappa are ref's.
FrenetState to_frenet_state(const CurveSample& ref, Scalar l, const CartesianState& c);

// The smallest SL rectangle holding the box's outline, grown by `margin` [m]
// on all four sides (obstacle_id 0, static: the caller names it). The outline is sampled at the corners and along each
// edge every kBoxEdgeSampleSpacing (at most kMaxBoxEdgeSamples points per
// edge), since on a curved road the extreme s or l can lie inside an edge.
template <class Cfg>
SlBox sl_bounding_box(const BasicReferenceLine<Cfg>& line, const OrientedBox& box, Scalar margin);

}  // namespace itp::geometry
