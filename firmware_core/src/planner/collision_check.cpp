#include "itp/planner/collision_check.hpp"

#include "itp/collision/box_overlap.hpp"
#include "itp/configurations.hpp"

namespace itp::planner {

template <class Cfg>
CollisionHit first_collision(const scene::BasicScene<Cfg>& scene,
                             std::span<const MotionSamples<Cfg>> motions,
                             const BasicPlan<Cfg>& plan) {
  static_assert(Cfg::kTrajectorySamples == Cfg::kStSamples, "one motion sample per trajectory sample");
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
      if (q.present &&
          collision::overlap(ego, geometry::OrientedBox{{q.x, q.y}, q.heading, o.length, o.width})) {
        return CollisionHit{static_cast<int>(k), o.id};
      }
    }
  }
  return CollisionHit{};
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                               \
  template CollisionHit first_collision<C>(const scene::BasicScene<C>&,                  \
                                           std::span<const MotionSamples<C>>,            \
                                           const BasicPlan<C>&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::planner
