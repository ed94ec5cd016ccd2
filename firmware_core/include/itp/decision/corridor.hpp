#pragma once
// The corridor of a decision: at each s, the l-interval of the decision's zone
// there (the intersection of both zones at a slice edge). Past the corridor's
// end the last zone continues (the speed stage stops the ego before it).
#include "itp/decision/convex_space.hpp"
#include "itp/decision/decision_tree.hpp"

namespace itp::decision {

struct LateralInterval {
  Scalar lo = 0;  // [m]
  Scalar hi = 0;  // [m]
  std::int16_t lo_box = kRoadEdge;  // what bounds it on the right: an obstacle's box, or the road
  std::int16_t hi_box = kRoadEdge;  // ... and on the left
  Scalar mid() const { return Scalar(0.5) * (lo + hi); }
};

// Where the path should run inside a zone: the middle of the gap when an
// obstacle bounds the zone (keep away from it), else the target lane centre
// clamped into the zone (a free road has no "middle" worth seeking).
Scalar zone_reference(const Zone& zone, Scalar l_target, Scalar half_width);

template <class Cfg>
LateralInterval corridor_at(const BasicConvexSpace<Cfg>& space, const BasicDecision<Cfg>& decision,
                            Scalar s);

}  // namespace itp::decision
