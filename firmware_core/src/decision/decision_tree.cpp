#include "itp/decision/decision_tree.hpp"

#include <array>
#include <cmath>

#include "itp/configurations.hpp"

namespace itp::decision {
namespace {

struct Frame {
  std::int16_t zone;      // zone at this depth
  std::int8_t next_bit;   // next successor bit to try
  Scalar cost;            // weighted cost of the path up to and including `zone`
  Scalar area, lane, link, move;  // unweighted parts
  Scalar l_anchor;        // [m] where the centre line entered this zone
  Scalar s_anchor;        // [m]
};

Scalar zone_cost(const Zone& z, const GeometricWeights& w) {
  return w.area * z.area_cost + w.lane * z.lane_cost;
}

Scalar mid(Scalar a, Scalar b) { return Scalar(0.5) * (a + b); }

// Keeps `kept` sorted ascending; equal costs keep the earlier path first.
template <class Cfg>
void offer(BasicDecisionSet<Cfg>& out, const BasicDecision<Cfg>& d) {
  auto& kept = out.kept;
  if (kept.full() && !(d.geometric_cost < kept.back().geometric_cost)) {
    return;
  }
  if (kept.full()) {
    kept.pop_back();
  }
  // Not full: popped above when it was (kKeptDecisions = capacity).
  static_cast<void>(kept.push_back(d));
  for (std::size_t i = kept.size() - 1; i > 0; --i) {  // < kKeptDecisions
    if (!(kept[i].geometric_cost < kept[i - 1].geometric_cost)) {
      break;
    }
    const BasicDecision<Cfg> tmp = kept[i];
    kept[i] = kept[i - 1];
    kept[i - 1] = tmp;
  }
}

}  // namespace

template <class Cfg>
void enumerate_decisions(const BasicConvexSpace<Cfg>& space, const GeometricWeights& w,
                         BasicDecisionSet<Cfg>& out, int max_nodes) {
  // The node cap of this search: kMaxTreeNodes, or less (what is left of the
  // cycle's budget). WCET: the loop below runs at most 2 kMaxTreeNodes + 2 times.
  const int node_cap = (max_nodes > 0 && max_nodes < Cfg::kMaxTreeNodes) ? max_nodes : Cfg::kMaxTreeNodes;
  out.kept.clear();
  out.nodes_expanded = 0;
  out.complete_paths = 0;
  out.truncated = false;
  if (space.start_zone < 0) {
    return;
  }
  const Scalar horizon = space.s_end - space.s_start;
  std::array<Frame, Cfg::kMaxSlices> stack{};
  int depth = 0;
  {
    const Zone& z0 = space.zones[static_cast<std::size_t>(space.start_zone)];
    const Scalar l0 = mid(z0.l_min, z0.l_max);
    stack[0] = Frame{space.start_zone, 0, zone_cost(z0, w), z0.area_cost, z0.lane_cost,
                     Scalar(0), Scalar(0), l0, space.slice_of(z0).s_begin};
  }
  out.nodes_expanded = 1;
  // Each pass either descends, backtracks or records a leaf; the node budget
  // bounds the descents, and backtracks never exceed descents + 1.
  for (int guard = 0; guard < 2 * Cfg::kMaxTreeNodes + 2 && depth >= 0; ++guard) {
    Frame& f = stack[static_cast<std::size_t>(depth)];
    const Zone& z = space.zones[static_cast<std::size_t>(f.zone)];
    const bool pruned = out.kept.full() && !(f.cost < out.kept.back().geometric_cost);
    if (f.next_bit == 0 && (z.successors == 0u || pruned)) {
      if (!pruned) {
        // Leaf: close the centre line to the zone's end and record the decision.
        BasicDecision<Cfg> d;
        for (int i = 0; i <= depth; ++i) {  // <= kMaxSlices
          // d is fresh; depth + 1 <= kMaxSlices (stack size) = capacity.
          static_cast<void>(d.zones.push_back(stack[static_cast<std::size_t>(i)].zone));
        }
        const Scalar ds = space.slice_of(z).s_end - f.s_anchor;
        const Scalar dl = mid(z.l_min, z.l_max) - f.l_anchor;
        d.move_cost = (f.move + std::sqrt(ds * ds + dl * dl)) / horizon;
        d.area_cost = f.area;
        d.lane_cost = f.lane;
        d.link_cost = f.link;
        d.reach = space.slice_of(z).s_end;
        d.reaches_end = d.reach >= space.s_end;
        const Scalar unreached = (space.s_end - d.reach) / horizon;
        d.geometric_cost = f.cost + w.move * d.move_cost + w.blocked * unreached;
        ++out.complete_paths;
        offer(out, d);
      }
      --depth;
      continue;
    }
    // Next successor of this zone, if any is left.
    int bit = f.next_bit;
    while (bit < Cfg::kMaxZonesPerSlice && (z.successors & (1u << bit)) == 0u) {
      ++bit;
    }
    if (bit >= Cfg::kMaxZonesPerSlice || pruned) {
      --depth;
      continue;
    }
    f.next_bit = static_cast<std::int8_t>(bit + 1);
    if (out.nodes_expanded >= node_cap) {
      out.truncated = true;
      break;
    }
    ++out.nodes_expanded;
    const Zone& c = space.successor(z, bit);
    const Scalar ov = BasicConvexSpace<Cfg>::overlap(z, c);
    // The centre line crosses the slice edge in the middle of the overlap.
    const Scalar l_cross = mid(z.l_min > c.l_min ? z.l_min : c.l_min, z.l_max < c.l_max ? z.l_max : c.l_max);
    const Scalar ds = space.slice_of(c).s_begin - f.s_anchor;
    const Scalar dl = l_cross - f.l_anchor;
    const Scalar link = space.vehicle_width / ov;
    Frame child;
    child.zone = static_cast<std::int16_t>(&c - space.zones.data());
    child.next_bit = 0;
    child.area = f.area + c.area_cost;
    child.lane = f.lane + c.lane_cost;
    child.link = f.link + link;
    child.move = f.move + std::sqrt(ds * ds + dl * dl);
    child.cost = f.cost + zone_cost(c, w) + w.link * link;
    child.l_anchor = l_cross;
    child.s_anchor = space.slice_of(c).s_begin;
    stack[static_cast<std::size_t>(++depth)] = child;
  }
}

template <class Cfg>
Side side_of(const BasicConvexSpace<Cfg>& space, const BasicDecision<Cfg>& decision,
             const SlBox& box) {
  for (std::int16_t zi : decision.zones) {  // <= kMaxSlices
    const Zone& z = space.zones[static_cast<std::size_t>(zi)];
    if (space.slice_of(z).s_end <= box.s_min || space.slice_of(z).s_begin >= box.s_max) {
      continue;  // this slice does not span the box
    }
    if (z.l_min >= box.l_max) {
      return Side::kLeft;
    }
    if (z.l_max <= box.l_min) {
      return Side::kRight;
    }
  }
  return Side::kNotReached;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                  \
  template void enumerate_decisions<C>(const BasicConvexSpace<C>&, const GeometricWeights&, \
                                       BasicDecisionSet<C>&, int);                          \
  template Side side_of<C>(const BasicConvexSpace<C>&, const BasicDecision<C>&, const SlBox&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::decision
