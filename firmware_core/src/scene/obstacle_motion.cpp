#include "itp/scene/obstacle_motion.hpp"

#include <bit>
#include <cmath>

#include "itp/configurations.hpp"
#include "itp/core/assert.hpp"
#include "itp/geometry/angle.hpp"

namespace itp::scene {

template <class Cfg>
ObstacleSample sample_pose(const BasicDynamicObstacle<Cfg>& obstacle, Scalar t) {
  const auto& traj = obstacle.trajectory;
  ITP_EXPECTS(!traj.empty());
  const int n = static_cast<int>(traj.size());
  ObstacleSample out;
  if (t < traj[0].t) {
    return out;  // not yet in the scene
  }
  out.present = true;
  const TimedPose& last = traj.back();
  if (t >= last.t) {
    const Scalar dt = t - last.t;
    out.x = last.x + last.v * dt * std::cos(last.heading);
    out.y = last.y + last.v * dt * std::sin(last.heading);
    out.heading = last.heading;
    out.v = last.v;
    return out;
  }
  constexpr int kSteps =
      static_cast<int>(std::bit_width(static_cast<unsigned>(Cfg::kMaxPredictionSamples))) + 1;
  int lo = 0;
  int hi = n - 1;
  for (int step = 0; step < kSteps && hi - lo > 1; ++step) {
    const int mid = (lo + hi) / 2;
    if (traj[static_cast<std::size_t>(mid)].t <= t) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  const TimedPose& a = traj[static_cast<std::size_t>(lo)];
  const TimedPose& b = traj[static_cast<std::size_t>(hi)];
  const Scalar f = (t - a.t) / (b.t - a.t);
  out.x = a.x + f * (b.x - a.x);
  out.y = a.y + f * (b.y - a.y);
  out.v = a.v + f * (b.v - a.v);
  out.heading = geometry::wrap_angle(a.heading + f * geometry::wrap_angle(b.heading - a.heading));
  return out;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C) \
  template ObstacleSample sample_pose<C>(const BasicDynamicObstacle<C>&, Scalar);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::scene
