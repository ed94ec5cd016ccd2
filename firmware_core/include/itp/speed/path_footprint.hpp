#pragma once
// What the ST graph asks of the planned path l(s) (paper 1.3): the speed
// bound along it, and whether its swept corridor meets an obstacle's SL box.
#include <array>

#include "itp/config.hpp"
#include "itp/geometry/sl_box.hpp"
#include "itp/path/path_optimizer.hpp"
#include "itp/speed/st_graph.hpp"

namespace itp::speed {

// The bound on s' (the rate of the reference's arc length) at path s: the
// road's limit and the lateral acceleration on the path's exact curvature,
// both on the world speed v = s' g (geometry::cartesian_motion).
template <class Cfg>
Scalar speed_limit_at(const path::BasicPathResult<Cfg>& path, const BasicStParams<Cfg>& p, Scalar s);

// Bounds of l(s) in each block of the path: its quintic's Bernstein
// coefficients on the block (convex hull property), widened by a slack far
// above the rounding of either side.
template <class Cfg>
struct LateralRange {
  std::array<Scalar, Cfg::kPathBlocks> lo{};  // [m]
  std::array<Scalar, Cfg::kPathBlocks> hi{};  // [m]
};

template <class Cfg>
void lateral_range(const path::BasicPathResult<Cfg>& path, LateralRange<Cfg>& r);

// Does the ego's swept path (half width + `lateral_margin` each side) overlap
// the box? Probes the path across the box's s-extent, unless l(s) over the
// blocks there (`range`) cannot reach the box at all.
template <class Cfg>
bool path_conflicts(const path::BasicPathResult<Cfg>& path, const LateralRange<Cfg>& range,
                    const BasicStParams<Cfg>& p, const geometry::SlBox& b, Scalar lateral_margin);

}  // namespace itp::speed
