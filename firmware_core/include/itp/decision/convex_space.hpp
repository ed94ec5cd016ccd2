#pragma once
// Paper 1.1, first half: the non-convex drivable SL area split into convex
// zones. The area is cut in s at every obstacle's s_min and s_max; in each
// s-slice the free l-intervals between obstacles are the zones (Zone_i_j:
// slice i, gap j). Zones narrower than the vehicle are dropped. A zone links
// to a zone of the next slice when their l-intervals overlap by at least the
// vehicle width. Fixed capacity: Cfg::kMaxSlices x Cfg::kMaxZonesPerSlice.
#include <cstdint>
#include <span>

#include "itp/config.hpp"
#include "itp/core/static_vector.hpp"
#include "itp/decision/road_sl.hpp"
#include "itp/geometry/sl_box.hpp"

namespace itp::decision {

using geometry::SlBox;

inline constexpr std::int16_t kRoadEdge = -1;  // a zone bounded by the road, not an obstacle

// Its s-range is its slice's (BasicConvexSpace::slice_of): kept once per
// slice, not per zone, the table being the decision stage's largest.
struct Zone {
  std::int16_t slice = 0;              // index into ConvexSpace::slices
  std::int16_t right_box = kRoadEdge;  // index of the box bounding it on the right
  std::int16_t left_box = kRoadEdge;   // ... and on the left
  std::uint16_t successors = 0;        // bit j: zone j of the next slice is linked
  Scalar l_min = 0;            // [m] right edge of the free interval
  Scalar l_max = 0;            // [m] left edge
  Scalar area_cost = 0;        // 1 - area / largest zone area: larger zones cost less
  Scalar lane_cost = 0;        // share of the target lane's width missing from the zone, [0, 1]

  Scalar width() const { return l_max - l_min; }
};

struct Slice {
  Scalar s_begin = 0;  // [m]
  Scalar s_end = 0;    // [m]
  std::int16_t first_zone = 0;  // index into ConvexSpace::zones
  std::int16_t zone_count = 0;
};

struct ConvexSpaceParams {
  Scalar s_start = 0;                  // [m] ego's s
  Scalar s_end = 0;                    // [m] end of the SL horizon (> s_start)
  Scalar vehicle_width = Scalar(1.9);  // [m] narrowest usable zone and link
  Scalar ego_l = 0;                    // [m] picks the start zone
};

enum class ConvexSpaceStatus : std::uint8_t {
  kOk = 0,
  kInvalidInput,  // s_end <= s_start, non-finite values, inverted boxes, too many boxes
  kNoStartZone,   // the ego's first slice has no free gap at all
};

const char* to_string(ConvexSpaceStatus status);

template <class Cfg>
struct BasicConvexSpace {
  StaticVector<Slice, Cfg::kMaxSlices> slices;
  StaticVector<Zone, Cfg::kMaxZones> zones;
  std::int16_t start_zone = -1;  // the ego's zone in slice 0
  Scalar s_start = 0;            // [m]
  Scalar s_end = 0;              // [m]
  Scalar vehicle_width = 0;      // [m]

  // Overlap of the l-intervals of two zones (negative when disjoint). [m]
  static Scalar overlap(const Zone& a, const Zone& b);
  const Zone& successor(const Zone& z, int bit) const;
  // The slice a zone lies in: its s-range [s_begin, s_end).
  const Slice& slice_of(const Zone& z) const { return slices[static_cast<std::size_t>(z.slice)]; }
};

// `boxes` may hold at most Cfg::kMaxDecisionObstacles entries; boxes outside
// [s_start, s_end] are ignored.
template <class Cfg>
ConvexSpaceStatus build_convex_space(const BasicRoadSl<Cfg>& road, std::span<const SlBox> boxes,
                                     const ConvexSpaceParams& params, BasicConvexSpace<Cfg>& out);

// The widest free l-interval of the road across [sa, sb] beside the boxes
// overlapping it (at most Cfg::kMaxDecisionObstacles). [m]
template <class Cfg>
Scalar widest_free_gap(const BasicRoadSl<Cfg>& road, std::span<const SlBox> boxes, Scalar sa,
                       Scalar sb);

// The least lateral move that puts a vehicle of `width` centred at l clear of
// the road edges and of the boxes overlapping [sa, sb]; infinity if no gap is
// wide enough. [m]
template <class Cfg>
Scalar lateral_move_to_free_gap(const BasicRoadSl<Cfg>& road, std::span<const SlBox> boxes, Scalar sa, Scalar sb,
                                Scalar l, Scalar width);

using ConvexSpace = BasicConvexSpace<DefaultConfig>;

}  // namespace itp::decision
