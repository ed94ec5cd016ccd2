#pragma once
// Frenet-frame helpers built on a ReferenceLine: heading <-> l' conversion and
// the SL bounding rectangle of an oriented box (paper 1.1, "SL block").
#include "itp/geometry/point.hpp"
#include "itp/geometry/reference_line.hpp"

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

// A rectangle in the world frame.
struct OrientedBox {
  Point2 center;                  // [m] box centre
  Scalar heading = Scalar(0);     // [rad] direction of the length axis
  Scalar length = Scalar(0);      // [m] along heading
  Scalar width = Scalar(0);       // [m] across heading
};

// Axis-aligned rectangle in the Frenet frame.
struct SLBox {
  Scalar s_min = Scalar(0);  // [m]
  Scalar s_max = Scalar(0);  // [m]
  Scalar l_min = Scalar(0);  // [m]
  Scalar l_max = Scalar(0);  // [m]
};

// The smallest SL rectangle holding the box's outline, grown by `margin` [m]
// on all four sides. The outline is sampled at the corners and along each
// edge every kBoxEdgeSampleSpacing (at most kMaxBoxEdgeSamples points per
// edge), since on a curved road the extreme s or l can lie inside an edge.
template <class Cfg>
SLBox sl_bounding_box(const BasicReferenceLine<Cfg>& line, const OrientedBox& box, Scalar margin);

}  // namespace itp::geometry
