#pragma once
// Paper 1.1, second half: the decision tree. Every path from the ego's zone
// through the zone graph is a convex combination (a decision: which side of
// each obstacle to pass). Paths end at the horizon or at a zone with no
// successor (the corridor is blocked there and the ego must stop before).
// They are ranked by geometric cost and the best K are kept.
//
// Search: depth-first with an explicit stack (no recursion), branch and bound
// on the partial cost (every cost term is >= 0, so a partial path that costs
// more than the K-th best kept one cannot win). Bounds: stack depth
// <= kMaxSlices, expanded nodes <= kMaxTreeNodes; memory is the stack plus K
// decisions.
#include <cstdint>

#include "itp/config.hpp"
#include "itp/core/static_vector.hpp"
#include "itp/decision/convex_space.hpp"

namespace itp::decision {

// Weights of the geometric cost (docs/decision.md). Pre-sorting uses every
// geometric term: area, lane and link costs summed over the zones, MoveCost,
// and a penalty for corridors that end before the horizon.
struct GeometricWeights {
  Scalar area = Scalar(1);      // w_area, per zone
  Scalar lane = Scalar(2);      // w_lane, per zone
  Scalar link = Scalar(0.5);    // per link: vehicle_width / overlap, in (0, 1]
  Scalar move = Scalar(1);      // w_move: centre-line length / horizon length
  Scalar blocked = Scalar(10);  // x share of the horizon the corridor does not reach
};

template <class Cfg>
struct BasicDecision {
  StaticVector<std::int16_t, Cfg::kMaxSlices> zones;  // one zone per slice, from slice 0
  Scalar area_cost = 0;      // sum of zone area costs (unweighted)
  Scalar lane_cost = 0;      // sum of zone lane costs (unweighted)
  Scalar link_cost = 0;      // sum of link costs (unweighted)
  Scalar move_cost = 0;      // centre-line length / horizon length (unweighted)
  Scalar geometric_cost = 0; // weighted sum, the pre-sort key
  Scalar reach = 0;          // [m] s where the corridor ends
  bool reaches_end = false;  // false: blocked before the horizon
};

template <class Cfg>
struct BasicDecisionSet {
  StaticVector<BasicDecision<Cfg>, Cfg::kKeptDecisions> kept;  // ascending geometric cost
  int nodes_expanded = 0;
  int complete_paths = 0;  // leaves reached (each a candidate decision)
  bool truncated = false;  // the node budget ran out before the search finished
};

template <class Cfg>
void enumerate_decisions(const BasicConvexSpace<Cfg>& space, const GeometricWeights& weights,
                         BasicDecisionSet<Cfg>& out, int max_nodes = 0);  // <= 0: kMaxTreeNodes

// Which side of a box a decision passes.
enum class Side : std::uint8_t {
  kNotReached = 0,  // the corridor ends before the box, or the box is outside the horizon
  kLeft,            // the corridor stays left of the box (greater l)
  kRight,
};

// Geometric: the corridor's zones in the slices the box spans lie left or right of it.
template <class Cfg>
Side side_of(const BasicConvexSpace<Cfg>& space, const BasicDecision<Cfg>& decision,
             const SlBox& box);

using Decision = BasicDecision<DefaultConfig>;
using DecisionSet = BasicDecisionSet<DefaultConfig>;

}  // namespace itp::decision
