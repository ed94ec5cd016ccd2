#include "itp/planner/collision_check.hpp"

#include <cmath>

#include "itp/collision/box_overlap.hpp"
#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"
#include "itp/geometry/frenet.hpp"

namespace itp::planner {
namespace {

constexpr Scalar kAlongHeading = Scalar(0.7853981633974483);  // [rad] 45 deg: coming the ego's way

// Is the hit of `o` at sample k a rear-end by a follower (see the header)?
template <class Cfg>
bool follower_runs_in(const scene::BasicScene<Cfg>& scene, const BasicPlan<Cfg>& plan, std::size_t k,
                      const scene::ObstacleSample& o, const scene::ObstacleSample* before,
                      const EgoLane& lane) {
  constexpr Scalar kDt = Cfg::kSpeedHorizon / static_cast<Scalar>(Cfg::kSpeedSamples);
  if (!(lane.lane_width > 0)) {
    return false;
  }
  const TrajectoryPoint& p = plan.trajectory[k];
  const Scalar rel = geometry::relative_heading(o.heading, p.heading);
  if (std::fabs(rel) > kAlongHeading) {
    return false;
  }
  const Scalar c = std::cos(p.heading);
  const Scalar sn = std::sin(p.heading);
  const Scalar half_length = Scalar(0.5) * scene.ego.geometry.length;
  const Scalar centre = half_length - scene::rear_overhang(scene.ego.geometry);  // rear axle to centre
  const Scalar along = (o.x - p.x) * c + (o.y - p.y) * sn - centre;
  // Its speed along the ego's heading: from its motion over the last step
  // when there is one (a recorded trajectory's speeds need not match it).
  const Scalar v_along = before != nullptr && before->present
                             ? ((o.x - before->x) * c + (o.y - before->y) * sn) / kDt
                             : o.v * std::cos(rel);
  if (along > -half_length || v_along <= max_of(p.v, Scalar(0))) {
    return false;
  }
  const Scalar half_lane = Scalar(0.5) * lane.lane_width;
  for (std::size_t j = 0; j <= k; ++j) {  // <= kTrajectorySamples
    if (std::fabs(plan.trajectory[j].l - lane.target_offset) > half_lane) {
      return false;
    }
  }
  return true;
}

}  // namespace

template <class Cfg>
CollisionHit first_collision(const scene::BasicScene<Cfg>& scene,
                             std::span<const MotionSamples<Cfg>> motions, const BasicPlan<Cfg>& plan,
                             const EgoLane& lane) {
  static_assert(Cfg::kTrajectorySamples == Cfg::kStSamples, "one motion sample per trajectory sample");
  bool rear_ended[Cfg::kMaxDynamicObstacles] = {};
  for (std::size_t k = 0; k < plan.trajectory.size(); ++k) {  // kTrajectorySamples
    const TrajectoryPoint& p = plan.trajectory[k];
    const geometry::OrientedBox ego = scene::footprint(scene.ego.geometry, {p.x, p.y}, p.heading);
    for (const scene::StaticObstacle& o : scene.static_obstacles) {  // <= kMaxStaticObstacles
      if (collision::overlap(ego, geometry::OrientedBox{{o.x, o.y}, o.heading, o.length, o.width})) {
        return CollisionHit{static_cast<int>(k), o.id};
      }
    }
    for (std::size_t i = 0; i < scene.dynamic_obstacles.size() && i < motions.size(); ++i) {  // <= kMaxDynamicObstacles
      const scene::BasicDynamicObstacle<Cfg>& o = scene.dynamic_obstacles[i];
      const scene::ObstacleSample& q = motions[i][k];
      if (!q.present || rear_ended[i] ||
          !collision::overlap(ego, geometry::OrientedBox{{q.x, q.y}, q.heading, o.length, o.width})) {
        continue;
      }
      rear_ended[i] = follower_runs_in(scene, plan, k, q, k > 0 ? &motions[i][k - 1] : nullptr, lane);
      if (!rear_ended[i]) {
        return CollisionHit{static_cast<int>(k), o.id};
      }
    }
  }
  return CollisionHit{};
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                         \
  template CollisionHit first_collision<C>(const scene::BasicScene<C>&,                            \
                                           std::span<const MotionSamples<C>>, const BasicPlan<C>&, \
                                           const EgoLane&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::planner
