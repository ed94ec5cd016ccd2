#pragma once
// A 64-bit digest of a scene and its time (FNV-1a over every value's bytes,
// field by field, so padding and container capacity never enter). The planner
// compares it with the last cycle's to answer a repeated request with the
// same plan (issue 13, defect 11). Not cryptographic: the link's MAC is.

#include <cstdint>
#include <cstring>

#include "itp/scene/scene.hpp"

namespace itp::scene {

class SceneDigest {
 public:
  // Bit patterns, so that -0 != +0 and NaNs digest by payload: "the same
  // scene" means the same bytes.
  void add(Scalar v) {
    unsigned char b[sizeof(Scalar)];
    std::memcpy(b, &v, sizeof(Scalar));
    add_bytes(b, sizeof(Scalar));
  }
  void add(std::int64_t v) {
    unsigned char b[sizeof(v)];
    std::memcpy(b, &v, sizeof(v));
    add_bytes(b, sizeof(v));
  }
  std::uint64_t value() const { return h_; }

 private:
  void add_bytes(const unsigned char* b, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {  // sizeof of one value
      h_ = (h_ ^ b[i]) * 0x100000001b3ULL;
    }
  }
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

template <class Cfg>
void add_boundary(SceneDigest& d, const BasicBoundary<Cfg>& b) {
  d.add(b.offset);
  d.add(static_cast<std::int64_t>(b.table.size()));
  for (const BoundaryPoint& p : b.table) {  // kMaxBoundaryPoints
    d.add(p.s);
    d.add(p.l);
  }
}

template <class Cfg>
std::uint64_t digest(const BasicScene<Cfg>& scene, Scalar now) {
  SceneDigest d;
  d.add(now);
  d.add(static_cast<std::int64_t>(scene.reference_line.size()));
  for (const geometry::Point2& p : scene.reference_line) {  // kMaxReferencePoints
    d.add(p.x);
    d.add(p.y);
  }
  const BasicRoad<Cfg>& road = scene.road;
  d.add(road.lane_width);
  add_boundary(d, road.left);
  add_boundary(d, road.right);
  d.add(road.target_lane_offset);
  d.add(road.speed_limit);
  const Ego& ego = scene.ego;
  for (const Scalar v : {ego.state.x, ego.state.y, ego.state.heading, ego.state.v, ego.state.a, ego.state.kappa,
                         ego.geometry.length, ego.geometry.width, ego.geometry.wheelbase, ego.limits.a_min,
                         ego.limits.a_max, ego.limits.lat_acc_max, ego.limits.kappa_max}) {
    d.add(v);
  }
  d.add(static_cast<std::int64_t>(scene.static_obstacles.size()));
  for (const StaticObstacle& o : scene.static_obstacles) {  // kMaxStaticObstacles
    d.add(static_cast<std::int64_t>(o.id));
    for (const Scalar v : {o.x, o.y, o.heading, o.length, o.width}) {
      d.add(v);
    }
  }
  d.add(static_cast<std::int64_t>(scene.dynamic_obstacles.size()));
  for (const BasicDynamicObstacle<Cfg>& o : scene.dynamic_obstacles) {  // kMaxDynamicObstacles
    d.add(static_cast<std::int64_t>(o.id));
    d.add(o.length);
    d.add(o.width);
    d.add(static_cast<std::int64_t>(o.trajectory.size()));
    for (const TimedPose& p : o.trajectory) {  // kMaxPredictionSamples
      for (const Scalar v : {p.t, p.x, p.y, p.heading, p.v}) {
        d.add(v);
      }
    }
  }
  return d.value();
}

}  // namespace itp::scene
