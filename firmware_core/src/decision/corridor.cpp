#include "itp/decision/corridor.hpp"

#include "itp/configurations.hpp"

namespace itp::decision {
namespace {
constexpr Scalar kSliceEps = Scalar(1e-6);  // [m] a sample on a slice edge belongs to both
}

Scalar zone_reference(const Zone& zone, Scalar l_target, Scalar half_width) {
  if (zone.left_box != kRoadEdge || zone.right_box != kRoadEdge) {
    return Scalar(0.5) * (zone.l_min + zone.l_max);
  }
  const Scalar lo = zone.l_min + half_width;
  const Scalar hi = zone.l_max - half_width;
  if (lo > hi) {
    return Scalar(0.5) * (zone.l_min + zone.l_max);
  }
  return l_target < lo ? lo : (l_target > hi ? hi : l_target);
}

template <class Cfg>
LateralInterval corridor_at(const BasicConvexSpace<Cfg>& space, const BasicDecision<Cfg>& decision,
                            Scalar s) {
  LateralInterval out;
  bool found = false;
  for (std::int16_t zi : decision.zones) {  // <= kMaxSlices
    const Zone& z = space.zones[static_cast<std::size_t>(zi)];
    if (space.slice_of(z).s_begin <= s + kSliceEps && s - kSliceEps <= space.slice_of(z).s_end) {
      if (!found) {
        out = LateralInterval{z.l_min, z.l_max, z.right_box, z.left_box};
        found = true;
      } else {
        if (z.l_min > out.lo) out.lo = z.l_min, out.lo_box = z.right_box;
        if (z.l_max < out.hi) out.hi = z.l_max, out.hi_box = z.left_box;
      }
    }
  }
  if (!found && !decision.zones.empty()) {
    // Before the first or past the last zone: continue the nearest end.
    const Zone& first = space.zones[static_cast<std::size_t>(decision.zones[0])];
    const Zone& last = space.zones[static_cast<std::size_t>(decision.zones.back())];
    const Zone& z = s < space.slice_of(first).s_begin ? first : last;
    out = LateralInterval{z.l_min, z.l_max, z.right_box, z.left_box};
  }
  return out;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                     \
  template LateralInterval corridor_at<C>(const BasicConvexSpace<C>&, const BasicDecision<C>&, \
                                          Scalar);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::decision
