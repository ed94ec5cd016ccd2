#pragma once
// Scenes for the planner tests, built in code with physical numbers.
#include <cmath>

#include "itp/scene/scene.hpp"

namespace planner_test {

using itp::Scalar;
using namespace itp::scene;

// A straight road along +x (reference line every 2 m), or an arc of radius R
// turning left (R > 0). SceneT: the scene type of the planner configuration.
template <class SceneT = Scene>
SceneT road_scene(double lanes_left, double lanes_right, double radius = 0, double length = 200) {
  SceneT s;
  for (double d = 0; d <= length + 1e-9; d += 2.0) {
    itp::geometry::Point2 p;
    if (radius > 0) {
      p.x = radius * std::sin(d / radius);
      p.y = radius * (1 - std::cos(d / radius));
    } else {
      p.x = d;
      p.y = 0;
    }
    (void)s.reference_line.push_back(p);
  }
  s.road.lane_width = 3.5;
  s.road.left.offset = 1.75 + 3.5 * lanes_left;
  s.road.right.offset = -1.75 - 3.5 * lanes_right;
  s.road.speed_limit = 15;
  s.ego.state.v = 10;
  return s;
}

template <class SceneT>
void add_static(SceneT& s, int id, double x, double y, double heading = 0, double length = 4.5,
                double width = 1.8) {
  StaticObstacle o;
  o.id = id;
  o.x = x;
  o.y = y;
  o.heading = heading;
  o.length = length;
  o.width = width;
  (void)s.static_obstacles.push_back(o);
}

// Constant velocity along heading, predicted every 0.1 s for `duration`.
template <class SceneT>
void add_mover(SceneT& s, int id, double x, double y, double heading, double v, double length = 4.5,
               double width = 1.8, double duration = 7.5) {
  typename decltype(s.dynamic_obstacles)::value_type o;
  o.id = id;
  o.length = length;
  o.width = width;
  for (double t = 0; t <= duration + 1e-9; t += 0.1) {
    TimedPose p;
    p.t = t;
    p.x = x + v * std::cos(heading) * t;
    p.y = y + v * std::sin(heading) * t;
    p.heading = heading;
    p.v = v;
    if (!o.trajectory.push_back(p)) break;
  }
  (void)s.dynamic_obstacles.push_back(o);
}

}  // namespace planner_test
