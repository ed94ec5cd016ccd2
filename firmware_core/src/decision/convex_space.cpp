#include "itp/decision/convex_space.hpp"

#include <array>
#include <cmath>
#include <limits>

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"

namespace itp::decision {
namespace {

// Cuts closer than this merge (the later one is dropped, so boxes only grow
// in s, never shrink): a car cannot change its lateral position within a
// sliver of free road between two obstacles, so such a slice must not link
// zones that the path could never connect.
constexpr Scalar kMinSliceLength = Scalar(2.0);  // [m]
template <class Cfg>
constexpr int kMaxCuts = 2 * Cfg::kMaxDecisionObstacles + 2 + Cfg::kMaxRoadCuts;

bool finite_box(const SlBox& b) {
  return std::isfinite(b.s_min) && std::isfinite(b.s_max) && std::isfinite(b.l_min) &&
         std::isfinite(b.l_max) && b.s_min <= b.s_max && b.l_min <= b.l_max;
}


// Sorted, de-duplicated cut positions in s: the slice edges (the boxes'
// ends and the road's cuts).
template <class Cfg>
int collect_cuts(const BasicRoadSl<Cfg>& road, std::span<const SlBox> boxes, Scalar s0, Scalar s1,
                 std::array<Scalar, kMaxCuts<Cfg>>& cuts) {
  int n = 0;
  cuts[static_cast<std::size_t>(n++)] = s0;
  for (const SlBox& b : boxes) {  // <= kMaxDecisionObstacles
    const Scalar edges[2] = {b.s_min, b.s_max};
    for (Scalar e : edges) {
      if (e > s0 && e < s1) {
        cuts[static_cast<std::size_t>(n++)] = e;
      }
    }
  }
  for (const Scalar e : road.cuts) {  // <= kMaxRoadCuts
    if (e > s0 && e < s1) {
      cuts[static_cast<std::size_t>(n++)] = e;
    }
  }
  cuts[static_cast<std::size_t>(n++)] = s1;
  // Insertion sort: n <= kMaxCuts, and deterministic for equal keys.
  for (int i = 1; i < n; ++i) {
    const Scalar v = cuts[static_cast<std::size_t>(i)];
    int j = i - 1;
    for (; j >= 0 && cuts[static_cast<std::size_t>(j)] > v; --j) {
      cuts[static_cast<std::size_t>(j + 1)] = cuts[static_cast<std::size_t>(j)];
    }
    cuts[static_cast<std::size_t>(j + 1)] = v;
  }
  int kept = 1;
  for (int i = 1; i < n; ++i) {  // <= kMaxCuts
    const Scalar v = cuts[static_cast<std::size_t>(i)];
    if (v - cuts[static_cast<std::size_t>(kept - 1)] >= kMinSliceLength) {
      cuts[static_cast<std::size_t>(kept++)] = v;
    } else if (kept == 1 && v > cuts[0]) {
      // The first cut stays too: the ego is already in the first slice (no
      // lateral move needed within it). Dropping a box's end just ahead of
      // the ego instead stretched the box over the whole next slice (a car
      // behind in the next lane whose sweep ends 1.7 m ahead narrowed the
      // ego's corridor for 34 m, and the ego stood outside it).
      cuts[static_cast<std::size_t>(kept++)] = v;
    } else if (i == n - 1) {
      // The horizon end always stays. Dropping the cut before it instead
      // would stretch the box that starts there back over the whole previous
      // slice (an obstacle entering the last 2 m of the horizon then blocked
      // its lanes from the ego on); a short last slice only ends the corridor.
      cuts[static_cast<std::size_t>(kept++)] = v;
    }
  }
  return kept;
}

struct Interval {
  Scalar lo;
  Scalar hi;
  std::int16_t box;
};

// The l-intervals of the boxes overlapping [sa, sb) and [road_lo, road_hi],
// sorted by their left edge (at most blocked.size()); returns their count.
int blocked_intervals(std::span<const SlBox> boxes, Scalar sa, Scalar sb, Scalar road_lo,
                      Scalar road_hi, std::span<Interval> blocked) {
  int n = 0;
  for (std::size_t i = 0; i < boxes.size() && static_cast<std::size_t>(n) < blocked.size(); ++i) {  // <= kMaxDecisionObstacles
    const SlBox& b = boxes[i];
    if (b.s_max > sa && b.s_min < sb && b.l_max > road_lo && b.l_min < road_hi) {
      blocked[static_cast<std::size_t>(n++)] = Interval{b.l_min, b.l_max, static_cast<std::int16_t>(i)};
    }
  }
  for (int i = 1; i < n; ++i) {  // insertion sort by lo; n <= kMaxDecisionObstacles
    const Interval v = blocked[static_cast<std::size_t>(i)];
    int j = i - 1;
    for (; j >= 0 && blocked[static_cast<std::size_t>(j)].lo > v.lo; --j) {
      blocked[static_cast<std::size_t>(j + 1)] = blocked[static_cast<std::size_t>(j)];
    }
    blocked[static_cast<std::size_t>(j + 1)] = v;
  }
  return n;
}

// Calls visit(g) for every free l-interval g of [road_lo, road_hi] between the
// boxes overlapping [sa, sb): n + 1 at most (some possibly empty), left to
// right, each with the boxes bounding it (kRoadEdge: the road).
struct Gap {
  Scalar lo = 0, hi = 0;
  std::int16_t lo_box = kRoadEdge, hi_box = kRoadEdge;
};
template <class Cfg, class Visit>
void for_each_gap(std::span<const SlBox> boxes, Scalar sa, Scalar sb, Scalar road_lo, Scalar road_hi, Visit&& visit) {
  std::array<Interval, Cfg::kMaxDecisionObstacles> blocked{};
  const int n = blocked_intervals(boxes, sa, sb, road_lo, road_hi, blocked);
  Gap g{road_lo, road_lo, kRoadEdge, kRoadEdge};
  for (int i = 0; i <= n; ++i) {  // n + 1 gaps at most: before each blocked interval, and after the last
    const bool last = i == n;
    g.hi = last ? road_hi : blocked[static_cast<std::size_t>(i)].lo;
    g.hi_box = last ? kRoadEdge : blocked[static_cast<std::size_t>(i)].box;
    visit(g);
    if (!last && blocked[static_cast<std::size_t>(i)].hi > g.lo) {
      g.lo = blocked[static_cast<std::size_t>(i)].hi;
      g.lo_box = blocked[static_cast<std::size_t>(i)].box;
    }
  }
}

// Free gaps of [road_lo, road_hi] between the boxes overlapping [sa, sb).
template <class Cfg>
void add_slice_zones(std::span<const SlBox> boxes, Scalar sa, Scalar sb, Scalar road_lo,
                     Scalar road_hi, const ConvexSpaceParams& params, std::int16_t slice_index,
                     BasicConvexSpace<Cfg>& out) {
  Slice slice;
  slice.s_begin = sa;
  slice.s_end = sb;
  slice.first_zone = static_cast<std::int16_t>(out.zones.size());
  for_each_gap<Cfg>(boxes, sa, sb, road_lo, road_hi, [&](const Gap& g) {
    if (g.hi - g.lo >= params.vehicle_width && slice.zone_count < Cfg::kMaxZonesPerSlice) {
      Zone z;
      z.slice = slice_index;
      z.l_min = g.lo;
      z.l_max = g.hi;
      z.right_box = g.lo_box;
      z.left_box = g.hi_box;
      // zone_count < kMaxZonesPerSlice per slice; over all slices at most
      // kMaxZones = capacity (config.hpp: the count of box/slice overlaps).
      static_cast<void>(out.zones.push_back(z));
      ++slice.zone_count;
    }
  });
  // One per cut interval: n_cuts - 1 <= kMaxCuts - 1 = kMaxSlices = capacity.
  static_cast<void>(out.slices.push_back(slice));
}

// The ego's first slice has no gap as wide as the vehicle, but the ego is
// there (half way past a parked car, an oncoming car's sweep beside it, its
// centre inside that sweep or a box's margin): the free gap nearest to the
// ego is the start zone, narrower than the vehicle, so that a plan can still
// take the ego out (the path QP admits the start, docs/path_speed.md;
// whether the plan is collision-free in time is the collision check's to
// decide). Without it there was no decision at all, and the ego stood there,
// in the oncoming lane.
template <class Cfg>
void add_start_gap(std::span<const SlBox> boxes, Scalar sa, Scalar sb, Scalar road_lo, Scalar road_hi, Scalar ego_l,
                   BasicConvexSpace<Cfg>& out) {
  Gap best;
  Scalar best_distance = std::numeric_limits<Scalar>::infinity();
  for_each_gap<Cfg>(boxes, sa, sb, road_lo, road_hi, [&](const Gap& g) {
    const Scalar distance = ego_l < g.lo ? g.lo - ego_l : (ego_l > g.hi ? ego_l - g.hi : Scalar(0));
    if (g.hi > g.lo && distance < best_distance) {
      best_distance = distance;
      best = g;
    }
  });
  if (best_distance < std::numeric_limits<Scalar>::infinity()) {
    Zone z;
    z.slice = 0;
    z.l_min = best.lo;
    z.l_max = best.hi;
    z.right_box = best.lo_box;
    z.left_box = best.hi_box;
    static_cast<void>(out.zones.push_back(z));  // slice 0 has no other zone: capacity as add_slice_zones
    ++out.slices[0].zone_count;
  }
}

template <class Cfg>
void compute_zone_costs(const BasicRoadSl<Cfg>& road, BasicConvexSpace<Cfg>& out) {
  Scalar area_max = 0;
  for (const Zone& z : out.zones) {  // <= kMaxZones
    const Scalar area = (out.slice_of(z).s_end - out.slice_of(z).s_begin) * z.width();
    area_max = area > area_max ? area : area_max;
  }
  const Scalar lane_lo = road.target_lane_offset - Scalar(0.5) * road.lane_width;
  const Scalar lane_hi = road.target_lane_offset + Scalar(0.5) * road.lane_width;
  for (Zone& z : out.zones) {  // <= kMaxZones
    const Scalar area = (out.slice_of(z).s_end - out.slice_of(z).s_begin) * z.width();
    z.area_cost = area_max > 0 ? Scalar(1) - area / area_max : Scalar(0);
    const Scalar lo = z.l_min > lane_lo ? z.l_min : lane_lo;
    const Scalar hi = z.l_max < lane_hi ? z.l_max : lane_hi;
    const Scalar covered = hi > lo ? hi - lo : Scalar(0);
    z.lane_cost = clamp(Scalar(1) - covered / road.lane_width, Scalar(0), Scalar(1));
  }
}

template <class Cfg>
void link_zones(BasicConvexSpace<Cfg>& out) {
  for (std::size_t i = 0; i + 1 < out.slices.size(); ++i) {  // < kMaxSlices
    const Slice& a = out.slices[i];
    const Slice& b = out.slices[i + 1];
    for (int za = 0; za < a.zone_count; ++za) {  // <= kMaxZonesPerSlice
      Zone& from = out.zones[static_cast<std::size_t>(a.first_zone + za)];
      for (int zb = 0; zb < b.zone_count; ++zb) {  // <= kMaxZonesPerSlice
        const Zone& to = out.zones[static_cast<std::size_t>(b.first_zone + zb)];
        // A narrow start zone (build_convex_space) links where the ego can
        // go on straight: to a zone that holds all of it.
        const Scalar need = from.width() < out.vehicle_width ? from.width() : out.vehicle_width;
        if (BasicConvexSpace<Cfg>::overlap(from, to) >= need) {
          from.successors = static_cast<std::uint16_t>(from.successors | (1u << zb));
        }
      }
    }
  }
}

}  // namespace

const char* to_string(ConvexSpaceStatus status) {
  switch (status) {
    case ConvexSpaceStatus::kOk: return "ok";
    case ConvexSpaceStatus::kInvalidInput: return "invalid_input";
    case ConvexSpaceStatus::kNoStartZone: return "no_start_zone";
  }
  return "unknown";
}

template <class Cfg>
Scalar BasicConvexSpace<Cfg>::overlap(const Zone& a, const Zone& b) {
  const Scalar lo = a.l_min > b.l_min ? a.l_min : b.l_min;
  const Scalar hi = a.l_max < b.l_max ? a.l_max : b.l_max;
  return hi - lo;
}

template <class Cfg>
const Zone& BasicConvexSpace<Cfg>::successor(const Zone& z, int bit) const {
  const Slice& next = slices[static_cast<std::size_t>(z.slice + 1)];
  return zones[static_cast<std::size_t>(next.first_zone + bit)];
}

template <class Cfg>
Scalar widest_free_gap(const BasicRoadSl<Cfg>& road, std::span<const SlBox> boxes, Scalar sa,
                       Scalar sb) {
  Scalar widest = 0;
  for_each_gap<Cfg>(boxes, sa, sb, road.right.max_over(sa, sb), road.left.min_over(sa, sb), [&widest](const Gap& g) {
    widest = g.hi - g.lo > widest ? g.hi - g.lo : widest;
  });
  return widest;
}

template <class Cfg>
Scalar lateral_move_to_free_gap(const BasicRoadSl<Cfg>& road, std::span<const SlBox> boxes, Scalar sa, Scalar sb,
                                Scalar l, Scalar width) {
  Scalar least = std::numeric_limits<Scalar>::infinity();
  for_each_gap<Cfg>(boxes, sa, sb, road.right.max_over(sa, sb), road.left.min_over(sa, sb), [&](const Gap& g) {
    if (g.hi - g.lo < width) return;
    // The centre positions that fit: [lo + w/2, hi - w/2].
    const Scalar a = g.lo + Scalar(0.5) * width;
    const Scalar b = g.hi - Scalar(0.5) * width;
    const Scalar move = l < a ? a - l : (l > b ? l - b : Scalar(0));
    least = move < least ? move : least;
  });
  return least;
}

template <class Cfg>
ConvexSpaceStatus build_convex_space(const BasicRoadSl<Cfg>& road, std::span<const SlBox> boxes,
                                     const ConvexSpaceParams& params, BasicConvexSpace<Cfg>& out) {
  out.slices.clear();
  out.zones.clear();
  out.start_zone = -1;
  out.s_start = params.s_start;
  out.s_end = params.s_end;
  out.vehicle_width = params.vehicle_width;
  if (!(params.s_end > params.s_start) || !std::isfinite(params.s_start) ||
      !std::isfinite(params.s_end) || !(params.vehicle_width > 0) || !std::isfinite(params.ego_l) ||
      boxes.size() > static_cast<std::size_t>(Cfg::kMaxDecisionObstacles) || road.left.empty() ||
      road.right.empty()) {
    return ConvexSpaceStatus::kInvalidInput;
  }
  for (const SlBox& b : boxes) {  // <= kMaxDecisionObstacles
    if (!finite_box(b)) {
      return ConvexSpaceStatus::kInvalidInput;
    }
  }
  std::array<Scalar, kMaxCuts<Cfg>> cuts{};
  const int n_cuts = collect_cuts<Cfg>(road, boxes, params.s_start, params.s_end, cuts);
  for (int i = 0; i + 1 < n_cuts; ++i) {  // < kMaxSlices
    const Scalar sa = cuts[static_cast<std::size_t>(i)];
    const Scalar sb = cuts[static_cast<std::size_t>(i + 1)];
    const Scalar road_lo = road.right.max_over(sa, sb);
    const Scalar road_hi = road.left.min_over(sa, sb);
    add_slice_zones(boxes, sa, sb, road_lo, road_hi, params, static_cast<std::int16_t>(i), out);
    if (i == 0 && out.slices[0].zone_count == 0) {
      add_start_gap(boxes, sa, sb, road_lo, road_hi, params.ego_l, out);
    }
  }
  compute_zone_costs(road, out);
  link_zones(out);

  // The start zone: the slice-0 zone holding the ego, else the nearest one.
  const Slice& first = out.slices[0];
  Scalar best = Scalar(0);
  for (int j = 0; j < first.zone_count; ++j) {  // <= kMaxZonesPerSlice
    const Zone& z = out.zones[static_cast<std::size_t>(first.first_zone + j)];
    const Scalar d = params.ego_l < z.l_min ? z.l_min - params.ego_l
                     : params.ego_l > z.l_max ? params.ego_l - z.l_max
                                              : Scalar(0);
    if (out.start_zone < 0 || d < best) {
      best = d;
      out.start_zone = static_cast<std::int16_t>(first.first_zone + j);
    }
  }
  return out.start_zone < 0 ? ConvexSpaceStatus::kNoStartZone : ConvexSpaceStatus::kOk;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                        \
  template struct BasicConvexSpace<C>;                                                            \
  template Scalar widest_free_gap<C>(const BasicRoadSl<C>&, std::span<const SlBox>, Scalar, Scalar); \
  template Scalar lateral_move_to_free_gap<C>(const BasicRoadSl<C>&, std::span<const SlBox>, Scalar, Scalar, \
                                              Scalar, Scalar);                                             \
  template ConvexSpaceStatus build_convex_space<C>(const BasicRoadSl<C>&, std::span<const SlBox>, \
                                                   const ConvexSpaceParams&,                      \
                                                   BasicConvexSpace<C>&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::decision
