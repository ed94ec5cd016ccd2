#pragma once
// A valid baseline scene for the scene tests, built in code.
#include "itp/scene/scene.hpp"

namespace scene_test {

using itp::Scalar;

inline itp::scene::Scene baseline_scene() {
  itp::scene::Scene s;
  for (int i = 0; i <= 30; ++i) {  // 150 m straight, every 5 m
    (void)s.reference_line.push_back({Scalar(5 * i), Scalar(0)});
  }
  s.road.lane_width = Scalar(3.5);
  s.road.left.offset = Scalar(5.25);
  s.road.right.offset = Scalar(-1.75);
  s.road.speed_limit = Scalar(16.7);
  s.ego.state = {Scalar(0), Scalar(0), Scalar(0), Scalar(10), Scalar(0), Scalar(0)};
  (void)s.static_obstacles.push_back({1, Scalar(40), Scalar(0.3), Scalar(0), Scalar(4.5), Scalar(1.8)});
  itp::scene::DynamicObstacle d;
  d.id = 11;
  d.length = Scalar(4.5);
  d.width = Scalar(1.8);
  (void)d.trajectory.push_back({Scalar(0), Scalar(20), Scalar(3.5), Scalar(0), Scalar(8)});
  (void)d.trajectory.push_back({Scalar(0.1), Scalar(20.8), Scalar(3.5), Scalar(0), Scalar(8)});
  (void)s.dynamic_obstacles.push_back(d);
  return s;
}

}  // namespace scene_test
