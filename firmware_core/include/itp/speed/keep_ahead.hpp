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

// The ego holding its speed: its acceleration ramps from a0 to 0 within one
// speed-QP block (the speed spline is C2), its speed then stays, below the
// speed bound v_hi, lowered (v_cap) where v_hi later drops faster than
// braking at `decel` (< 0) follows. Keeping ahead of a follower asks for no
// more than this (and the latest braking after it): not braking before what
// lies ahead needs. (Asking for the furthest reachable motion, at a_max,
// pinned the speed QP to it within 0.2 m, and a C2 spline does not follow
// such a profile that closely: infeasible.)
template <class Cfg>
void holding(const BasicStParams<Cfg>& p, const BasicSpeedBounds<Cfg>& b, Scalar decel, BasicEgoProfile<Cfg>& r);

// The latest braking: `r` (holding) up to a switch sample, then the
// acceleration ramps down to `decel` (< 0) within one speed-QP block (the
// spline's acceleration is continuous) and holds it to a stop; the latest switch whose motion stays within every upper bound s_hi
// below `s_limit` (bounds at or beyond it, the end of the planned path, are
// not a stop), with `tolerance`. Fills `late` and returns true; false when
// even braking at once (switch 0) crosses a bound.
// WCET: <= Cfg::kStSamples switches x Cfg::kStSamples samples.
template <class Cfg>
bool latest_braking(const BasicSpeedBounds<Cfg>& b, const BasicEgoProfile<Cfg>& r, Scalar decel, Scalar s_limit,
                    Scalar tolerance, std::array<Scalar, Cfg::kStSamples>& late);

// Where the follower's footprint is in line with the path, the ego's rear
// stays ahead of its front by the conflict zone's margin, but never ahead of
// `late` (holding the speed, then the latest braking at comfort_decel: a
// motion that keeps every bound) less a slack growing with time. Returns whether a lower bound of `b` was raised.
template <class Cfg>
bool keep_ahead(const BasicStDecision<Cfg>& d, const BasicDynamicTrack<Cfg>& tr,
                const path::BasicPathResult<Cfg>& path, const BasicStParams<Cfg>& p,
                const std::array<Scalar, Cfg::kStSamples>& late, BasicSpeedBounds<Cfg>& b);

}  // namespace itp::speed
