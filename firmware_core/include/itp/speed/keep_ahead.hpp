#pragma once
// Followers in the ST graph: a faster road user closing in from behind is
// ignored (the gap is its to keep, RSS), and the ego keeps ahead of it where
// it is in line with the path, as far as braking for what lies ahead allows
// (an ego that brakes earlier than it must gets hit by traffic that does not
// react).
//
// The lower bounds this raises are feasible by construction: never ahead of
// one motion the ego can drive within the speed QP's limits and every upper
// bound (`latest_braking`). An infeasible keep-ahead bound (a stop before the
// map's end with a car close behind) cost the speed QP about 70 active-set
// iterations to certify, in every step of the planner's iteration.
#include <array>

#include "itp/path/path_optimizer.hpp"
#include "itp/speed/speed_optimizer.hpp"
#include "itp/speed/st_graph.hpp"

namespace itp::speed {

// The motion the keep-ahead bound never asks more than: the ego holding its
// speed (acceleration a0 -> 0 within one speed-QP block: the spline is C2) up
// to sample m, then braking (acceleration ramped to `decel` < 0 within one
// block, then held to a stop). Holding, not the furthest reachable motion at
// a_max: asking for that pinned the speed QP within 0.2 m of it, and a C2
// spline does not follow such a profile that closely (infeasible).
//
// The latest m whose motion keeps every upper bound s_hi below `s_limit`
// (bounds at or beyond it, the end of the planned path, are not a stop) with
// `tolerance`, and every speed bound v_hi, and stops before a stop at the
// horizon's end after the horizon too; -1 when even braking at once does not.
template <class Cfg>
int latest_braking(const BasicStParams<Cfg>& p, const BasicSpeedBounds<Cfg>& b, Scalar decel, Scalar s_limit,
                   Scalar tolerance);

// That motion's speed-s at every ST sample (for checks).
template <class Cfg>
void braking_motion(const BasicStParams<Cfg>& p, int m, Scalar decel, std::array<Scalar, Cfg::kStSamples>& s);

// Where the follower's footprint is in line with the path, the ego's rear
// stays ahead of its front by the conflict zone's margin, but never ahead of
// the motion (m, decel) less a slack growing with time; at the speed spline's
// knots. Returns whether a lower bound of `b` was raised.
template <class Cfg>
bool keep_ahead(const BasicStDecision<Cfg>& d, const BasicDynamicTrack<Cfg>& tr,
                const path::BasicPathResult<Cfg>& path, const BasicStParams<Cfg>& p, int m, Scalar decel,
                BasicSpeedBounds<Cfg>& b);

}  // namespace itp::speed
