#include "itp/planner/road_prediction.hpp"

#include <cmath>

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"
#include "itp/geometry/angle.hpp"

namespace itp::planner {
namespace {

constexpr Scalar kStraightHeading = Scalar(1e-6);  // [rad] equal headings: a straight line
constexpr Scalar kStraightSpeed = Scalar(1e-6);    // [m/s] equal speeds
constexpr Scalar kCollinear = Scalar(0.01);        // [m] off the line through the first pose
constexpr Scalar kMovingSpeed = Scalar(0.5);       // [m/s] slower: standing, used as given
// Across the road (45..135 deg from the reference): a crossing mover, as given.
constexpr Scalar kAlongHeading = Scalar(0.7853981633974483);    // [rad]
constexpr Scalar kOncomingHeading = Scalar(2.356194490192345);  // [rad]
// Sideways faster than this: a lane change under way, which ends at the next
// lane centre; slower: the obstacle keeps its lateral offset.
constexpr Scalar kLaneChangeSpeed = Scalar(0.5);  // [m/s]
constexpr Scalar kOffRoad = Scalar(1);            // [m] beyond the edges: not a road user
constexpr Scalar kMinScale = Scalar(0.2);         // floor of 1 - kappa l (inside a tight bend)

// Does the prediction run on a straight line at constant heading and speed?
template <class Cfg>
bool straight_line(const scene::BasicDynamicObstacle<Cfg>& o) {
  const scene::TimedPose& a = o.trajectory[0];
  const Scalar cx = std::cos(a.heading);
  const Scalar cy = std::sin(a.heading);
  for (const scene::TimedPose& p : o.trajectory) {  // <= kMaxPredictionSamples
    const Scalar off = (p.x - a.x) * cy - (p.y - a.y) * cx;  // distance from the line
    if (std::fabs(geometry::wrap_angle(p.heading - a.heading)) > kStraightHeading ||
        std::fabs(p.v - a.v) > kStraightSpeed || std::fabs(off) > kCollinear) {
      return false;
    }
  }
  return true;
}


// The lane centre a sideways motion from l at lateral speed v_l ends at:
// the next one in its direction (lanes at origin + j width).
Scalar lane_change_target(Scalar l, Scalar v_l, Scalar origin, Scalar width) {
  const Scalar j = (l - origin) / width;
  const Scalar target = v_l > 0 ? std::floor(j) + Scalar(1) : std::ceil(j) - Scalar(1);
  return origin + target * width;
}

}  // namespace

template <class Cfg>
PredictionUse predict_along_road(const geometry::BasicReferenceLine<Cfg>& line,
                                 const decision::BasicRoadSl<Cfg>& road,
                                 const scene::BasicDynamicObstacle<Cfg>& o, Scalar now, Scalar dt,
                                 std::array<scene::ObstacleSample, Cfg::kStSamples>& out) {
  for (int k = 0; k < Cfg::kStSamples; ++k) {  // Cfg::kStSamples
    out[static_cast<std::size_t>(k)] = scene::sample_pose(o, now + dt * static_cast<Scalar>(k));
  }
  if (!straight_line(o)) {
    return PredictionUse::kAsGiven;
  }
  // The anchor: the first sample on the reference line (beyond its ends the
  // frame runs straight on, not along the road: no road to follow there).
  // Samples before it stay as given.
  int first = -1;
  int first_present = -1;
  geometry::CurveSample foot;
  geometry::FrenetPoint f0;
  for (int k = 0; k < Cfg::kStSamples && first < 0; ++k) {  // Cfg::kStSamples
    const scene::ObstacleSample& q = out[static_cast<std::size_t>(k)];
    if (q.present) {
      first_present = first_present < 0 ? k : first_present;
      f0 = line.to_frenet(geometry::Point2{q.x, q.y}, foot);
      if (f0.s >= 0 && f0.s <= line.length()) {
        first = k;
      }
    }
  }
  if (first < 0) {
    return PredictionUse::kAsGiven;
  }
  const scene::ObstacleSample p0 = out[static_cast<std::size_t>(first)];
  const Scalar rel0 = geometry::wrap_angle(p0.heading - foot.heading);
  const bool along = std::fabs(rel0) <= kAlongHeading || std::fabs(rel0) >= kOncomingHeading;
  const Scalar right = road.right.at(f0.s);
  const Scalar left = road.left.at(f0.s);
  const bool on_road = f0.l > right - kOffRoad && f0.l < left + kOffRoad;
  if (!along || !on_road || std::fabs(p0.v) < kMovingSpeed) {
    return PredictionUse::kAsGiven;
  }
  const Scalar v_s = p0.v * std::cos(rel0);  // [m/s] along the reference (< 0: oncoming)
  Scalar v_l = p0.v * std::sin(rel0);        // [m/s] sideways
  Scalar l_end = f0.l;                       // where the sideways motion ends
  // Seen first behind the reference line's start (traffic behind the ego's
  // window), the obstacle's heading is compared with the road where its
  // straight-line extrapolation reaches the line, not where it is: on a curve
  // that difference is the bend, not a lane change (a car 50 m behind in the
  // next lane of a 264 m bend read as moving sideways at 0.5 m/s into the
  // ego's lane, whose sweep then covered the ego). It keeps its offset.
  const bool seen_on_line = first == first_present;
  if (std::fabs(v_l) >= kLaneChangeSpeed && seen_on_line) {
    l_end = clamp(lane_change_target(f0.l, v_l, road.target_lane_offset, road.lane_width), right, left);
    if ((l_end - f0.l) * v_l <= 0) {
      v_l = 0;  // already at (or beyond) the edge it moves towards
      l_end = f0.l;
    }
  } else {
    v_l = 0;
  }
  Scalar s = f0.s;
  Scalar l = f0.l;
  for (int k = first; k < Cfg::kStSamples; ++k) {  // Cfg::kStSamples
    const auto u = static_cast<std::size_t>(k);
    const geometry::CurveSample r = line.evaluate(s);
    const bool sideways = v_l != 0 && (l_end - l) * v_l > 0;
    const Scalar rel = sideways ? rel0 : (v_s >= 0 ? Scalar(0) : Scalar(3.141592653589793));
    scene::ObstacleSample& q = out[u];
    q.present = true;
    q.x = r.position.x - l * std::sin(r.heading);
    q.y = r.position.y + l * std::cos(r.heading);
    q.heading = geometry::wrap_angle(r.heading + rel);
    q.v = p0.v;
    // Next sample: along the lane at offset l (ds_ref = ds_lane / (1 - kappa l)),
    // sideways until the target lane centre.
    const Scalar scale = Scalar(1) - r.kappa * l;
    s += v_s * dt / (scale > kMinScale ? scale : kMinScale);
    if (sideways) {
      const Scalar next = l + v_l * dt;
      l = (l_end - next) * v_l > 0 ? next : l_end;
    }
  }
  return PredictionUse::kFollowsRoad;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                    \
  template PredictionUse predict_along_road<C>(                                               \
      const geometry::BasicReferenceLine<C>&, const decision::BasicRoadSl<C>&,                \
      const scene::BasicDynamicObstacle<C>&, Scalar, Scalar,                                  \
      std::array<scene::ObstacleSample, C::kStSamples>&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::planner
