#pragma once
// Physical checks of a returned plan, independent of the planner's internals:
// clearances from the real oriented boxes with the simulator's own geometry
// (hil::sim, an oracle that shares no code with the planner's collision
// check), limits recomputed from the trajectory samples. Templates, so that every planner configuration is
// checked the same way.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "heap_guard.hpp"
#include "itp/planner/planner.hpp"
#include "itp/scene/obstacle_motion.hpp"
#include "itp/scene/scene.hpp"
#include "sim/box_geometry.hpp"

namespace planner_test {

// One planner of configuration Cfg and its output, on the heap (the objects
// are large); go() plans one cycle under the heap guard, which fails the
// test on any allocation during planning.
template <class Cfg>
struct PlanRun {
  std::unique_ptr<itp::planner::BasicPlanner<Cfg>> planner =
      std::make_unique<itp::planner::BasicPlanner<Cfg>>();
  std::unique_ptr<itp::planner::BasicPlan<Cfg>> plan = std::make_unique<itp::planner::BasicPlan<Cfg>>();
  itp::PlanStatus status = itp::PlanStatus::kInvalidInput;

  void go(const itp::scene::BasicScene<Cfg>& s, double now = 0) {
    itp::planner::BasicPlanRequest<Cfg> req{&s, now};
    test_support::HeapGuard guard;
    status = planner->plan(req, *plan);
  }
};

template <class S>
double rear_overhang(const S& s) {
  return 0.5 * (s.ego.geometry.length - s.ego.geometry.wheelbase);
}

// The plan's decision for obstacle `id` (a default one, side kNone and
// longitudinal kIgnore, when the plan does not name it).
template <class P>
itp::planner::ObstacleDecision decision_for(const P& plan, std::int32_t id) {
  itp::planner::ObstacleDecision found;
  for (const itp::planner::ObstacleDecision& d : plan.decisions) {
    if (d.obstacle == id) found = d;
  }
  return found;
}

// Smallest distance between the ego's footprint and any obstacle over the plan.
template <class S, class P>
double min_clearance(const S& s, const P& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const itp::planner::TrajectoryPoint& q : p.trajectory) {
    const hil::sim::OrientedBox ego =
        hil::sim::ego_box(hil::sim::Pose{q.x, q.y, q.heading}, s.ego.geometry.length, s.ego.geometry.width,
                          s.ego.geometry.wheelbase);
    for (const auto& o : s.static_obstacles) {
      best = std::min(best, hil::sim::box_distance(ego, {o.x, o.y, o.heading, o.length, o.width}));
    }
    for (const auto& o : s.dynamic_obstacles) {
      const auto pose = itp::scene::sample_pose(o, q.t);
      if (pose.present) {
        best = std::min(best, hil::sim::box_distance(ego, {pose.x, pose.y, pose.heading, o.length, o.width}));
      }
    }
  }
  return best;
}

// Limits every returned trajectory must respect, recomputed from its samples.
template <class Cfg>
void check_limits(const itp::scene::BasicScene<Cfg>& s, const itp::planner::BasicPlan<Cfg>& p) {
  REQUIRE(p.trajectory.size() == static_cast<std::size_t>(Cfg::kTrajectorySamples));
  const auto& lim = s.ego.limits;
  for (std::size_t k = 0; k < p.trajectory.size(); ++k) {
    const itp::planner::TrajectoryPoint& q = p.trajectory[k];
    CHECK(std::isfinite(q.x));
    CHECK(std::isfinite(q.y));
    CHECK(q.t == doctest::Approx(0.1 * static_cast<double>(k)));
    CHECK(q.v >= -1e-6);
    CHECK(q.a <= lim.a_max + 0.2);
    CHECK(q.a >= lim.a_min - 0.2);
    CHECK(std::fabs(q.kappa) <= lim.kappa_max + 1e-3);
    CHECK(std::fabs(q.v * q.v * q.kappa) <= lim.lat_acc_max + 0.3);
    if (k > 0) {
      // Positions advance consistently with the speed (finite differences).
      const itp::planner::TrajectoryPoint& a = p.trajectory[k - 1];
      const double step = std::hypot(q.x - a.x, q.y - a.y);
      CHECK(step == doctest::Approx(0.05 * (a.v + q.v)).epsilon(0.1).scale(1.0));
    }
  }
  // Road boundaries: every ego corner inside [right, left] (lateral offset l).
  for (const itp::planner::TrajectoryPoint& q : p.trajectory) {
    CHECK(q.l + 0.5 * s.ego.geometry.width <= s.road.left.offset + 0.2);
    CHECK(q.l - 0.5 * s.ego.geometry.width >= s.road.right.offset - 0.2);
  }
}

}  // namespace planner_test
