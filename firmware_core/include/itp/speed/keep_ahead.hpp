#pragma once
// Followers in the ST graph: a faster road user closing in from behind is
// ignored (the gap is its to keep, RSS), and the ego keeps ahead of it where
// it is in line with the path, as far as braking for what lies ahead allows
// (an ego that brakes earlier than it must gets hit by traffic that does not
// react).
#include <array>

#include "itp/path/path_optimizer.hpp"
#include "itp/speed/speed_optimizer.hpp"
#include "itp/speed/st_graph.hpp"

namespace itp::speed {

// The furthest the ego can be at each ST sample: its acceleration ramps from
// a0 to a_max within one speed-QP block (the speed spline is C2), then holds
// it up to the speed bound.
template <class Cfg>
void reachable(const BasicStParams<Cfg>& p, const BasicSpeedBounds<Cfg>& b,
               std::array<Scalar, Cfg::kStSamples>& s_max);

// Where the follower's footprint is in line with the path, the ego's rear
// stays ahead of its front by the conflict zone's margin, as long as braking
// at comfort_decel from the follower's speed still meets every later upper
// bound (the end of the planned path is none: not a stop) and the ego can get
// there at all (`s_max`). Returns whether a lower bound of `b` was raised.
template <class Cfg>
bool keep_ahead(const BasicStDecision<Cfg>& d, const BasicDynamicTrack<Cfg>& tr,
                const path::BasicPathResult<Cfg>& path, const BasicStParams<Cfg>& p,
                const std::array<Scalar, Cfg::kStSamples>& s_max, BasicSpeedBounds<Cfg>& b);

}  // namespace itp::speed
