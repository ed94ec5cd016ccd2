#pragma once
// Fitting a road to the planner's capacities (docs/commonroad.md, "Resampling"):
//  - a road edge l(s) with more knots than a boundary holds becomes one with at
//    most N knots that never lies outside the true edge (the left edge never
//    further left, the right edge never further right), as close as the knot
//    budget allows;
//  - a reference polyline with more points than the planner holds becomes a
//    subset of its own vertices that stays within a measured distance of it.
// Both report their exact worst-case error, which the caller can add as a margin.
#include <span>
#include <vector>

#include "sim/world.hpp"

namespace hil::sim {

enum class EdgeSide { kLeft, kRight };

struct EdgeFit {
  std::vector<Boundary::Knot> knots;  // ascending s, at most the requested number
  double max_narrowing = 0.0;         // [m] max over [s_begin, s_end] of |truth - fit| (fit inside)
};

// The piecewise-linear edge `truth` (held constant beyond its first and last
// knot, as scene/1 and the planner read it) restricted to [s_begin, s_end] and
// fitted with at most max_knots knots (>= 2) that lie inside the road:
// fit(s) <= truth(s) for the left edge, >= for the right, for every s in
// [s_begin, s_end]. When truth has few enough knots there, they are copied
// (exact). Otherwise the better of two fits, by their exact worst error:
//  - greedy segments in the band [truth - tol, truth] (left edge), knots at
//    some of the truth's knots, tol bisected down to the smallest that fits
//    (noise in the truth smaller than tol costs no knots);
//  - a uniform grid of max_knots knots, spacing h, each knot at the minimum of
//    the truth over its two neighbouring intervals: the gap is then at most
//    the truth's oscillation over any 3h (<= 3 h max|dl/ds|).
EdgeFit fit_edge_inside(std::span<const Boundary::Knot> truth, double s_begin, double s_end, int max_knots,
                        EdgeSide side);

// Exact largest |truth - fit| over [s_begin, s_end] of two piecewise-linear
// functions (constant beyond their ends): the maximum of a difference of
// piecewise-linear functions lies at a knot of one of them.
double max_edge_gap(std::span<const Boundary::Knot> truth, std::span<const Boundary::Knot> fit, double s_begin,
                    double s_end);

// Piecewise-linear evaluation, constant beyond the ends (Boundary::at semantics).
double edge_at(std::span<const Boundary::Knot> knots, double s);

struct PolylineFit {
  std::vector<Point2> points;   // a subset of the input's vertices, first and last kept
  double max_deviation = 0.0;   // [m] Hausdorff distance between input and output polylines
};

// At most max_points (>= 2) of the polyline's vertices. Greedy: from each kept
// vertex, the farthest next vertex such that every skipped vertex lies within
// a tolerance of the chord and the chord is at most max_chord long (the
// planner's spline is documented up to 5 m spacing); the tolerance is bisected
// down to the smallest that fits. Every skipped stretch is straight between
// vertices, so its distance to the chord is largest at a vertex: the reported
// deviation is exact. A polyline that already fits is returned unchanged.
PolylineFit simplify_polyline(std::span<const Point2> line, int max_points, double max_chord = 5.0);

}  // namespace hil::sim
