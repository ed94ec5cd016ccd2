// The scene generator: reproducible, inside the paper's envelope, and
// solvable by the rules of docs/simulation.md, each checked here independently
// from the written world (polyline projection, true boxes, pose_at).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "sim/box_geometry.hpp"
#include "sim/scene_generator.hpp"

using namespace hil::sim;

namespace {
constexpr std::uint64_t kSeed = 20240611;
constexpr int kScenes = 300;

const std::vector<World>& suite() {
  static const std::vector<World> s = default_suite(kScenes, kSeed);
  return s;
}

// Points covering a box (5 x 5 grid including the corners).
std::vector<Point2> box_points(const OrientedBox& b) {
  std::vector<Point2> pts;
  const double c = std::cos(b.heading), s = std::sin(b.heading);
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j) {
      const double u = (i / 4.0 - 0.5) * b.length, v = (j / 4.0 - 0.5) * b.width;
      pts.push_back({b.cx + u * c - v * s, b.cy + u * s + v * c});
    }
  return pts;
}

// The ego driving its lane at constant speed: rear axle at s = v t, l = 0.
OrientedBox ego_at(const World& w, const std::vector<double>& sv, double t) {
  const Pose p = polyline_pose(w.reference_line, sv, w.ego.v * t);
  return ego_box(p, w.ego.length, w.ego.width, w.ego.wheelbase);
}
}  // namespace

TEST_CASE("generator: same seed and index give identical JSON, others differ") {
  const std::string a = scene_to_text(generate_scene(7, 3));
  CHECK(a == scene_to_text(generate_scene(7, 3)));
  CHECK(a != scene_to_text(generate_scene(7, 4)));
  CHECK(a != scene_to_text(generate_scene(8, 3)));
  CHECK(scene_to_text(suite()[17]) == scene_to_text(generate_scene(kSeed, 17)));
  CHECK(suite()[42].name == "paper-0042");
}

TEST_CASE("generator: 300 scenes inside the paper's envelope") {
  std::map<std::string, int> kinds;
  std::set<std::string> shapes;
  for (const World& w : suite()) {
    CAPTURE(w.name);
    CHECK(w.static_obstacles.size() >= 1);
    CHECK(w.static_obstacles.size() <= 10);
    CHECK(w.dynamic_obstacles.size() >= 1);
    CHECK(w.dynamic_obstacles.size() <= 5);
    CHECK(w.road.speed_limit >= 8.0);
    CHECK(w.road.speed_limit <= 20.0);
    CHECK(w.ego.v > 0.0);
    CHECK(w.ego.v <= w.road.speed_limit);
    CHECK(w.road.lane_width == 3.5);
    // 2 or 3 lanes, the ego in the rightmost or the middle one.
    const double lanes = (w.road.left_boundary.at(0) - w.road.right_boundary.at(0)) / w.road.lane_width;
    CHECK((std::abs(lanes - 2.0) < 1e-9 || std::abs(lanes - 3.0) < 1e-9));
    const double right = w.road.right_boundary.at(0);
    CHECK((std::abs(right + 1.75) < 1e-9 || (std::abs(right + 5.25) < 1e-9 && lanes > 2.5)));
    // Reference line: >= 150 m (a road that ends: room for a comfortable stop
    // and 25 m more), every 2 m, radius >= 50 m.
    const auto sv = polyline_arc_lengths(w.reference_line);
    const bool map_end = std::find(w.tags.begin(), w.tags.end(), "map_end") != w.tags.end();
    if (map_end) {
      CHECK(sv.back() >= 3.8 + w.ego.v * w.ego.v / 6.0 + 25.0 - 2.0);
      CHECK(sv.back() >= 79.0);
      ++kinds["map_end"];
    } else {
      CHECK(sv.back() >= 149.0);
    }
    for (std::size_t i = 1; i < w.reference_line.size(); ++i) {
      CHECK(sv[i] - sv[i - 1] == doctest::Approx(2.0).epsilon(1e-3));
    }
    for (std::size_t i = 1; i + 1 < w.reference_line.size(); ++i) {
      const Point2 a = w.reference_line[i - 1], b = w.reference_line[i], c = w.reference_line[i + 1];
      const double turn = std::abs(std::remainder(std::atan2(c.y - b.y, c.x - b.x) - std::atan2(b.y - a.y, b.x - a.x), 2 * std::numbers::pi));
      CHECK(turn / 2.0 <= 1.0 / 50.0 + 1e-6);
    }
    // Ego at s = 0 on its lane centre.
    const PolylineProjection ep = project_to_polyline(w.reference_line, w.ego.x, w.ego.y);
    CHECK(std::abs(ep.s) < 0.5);
    CHECK(std::abs(ep.l) < 0.05);
    // Dynamic trajectories every 0.1 s to the end of the run.
    for (const auto& d : w.dynamic_obstacles) {
      REQUIRE(d.trajectory.size() >= 2);
      CHECK(d.trajectory.back().t == doctest::Approx(w.duration.value_or(0)));
      for (std::size_t k = 1; k < d.trajectory.size(); ++k) {
        CHECK(d.trajectory[k].t - d.trajectory[k - 1].t == doctest::Approx(0.1));
      }
      ++kinds[d.kind];
    }
    for (const auto& o : w.static_obstacles) ++kinds[o.kind];
    shapes.insert(w.tags.front());
  }
  for (const char* k : {"parked_car", "debris", "slow_leader", "adjacent_car", "cut_in", "oncoming", "pedestrian",
                        "cyclist", "cut_in_brake", "overtaker", "map_end"}) {
    CAPTURE(k);
    CHECK(kinds[k] >= 10);
  }
  CHECK(shapes == std::set<std::string>{"road:arc", "road:s-curve", "road:straight"});
  for (const auto& [k, n] : kinds) MESSAGE(k << ": " << n);
}

TEST_CASE("generator: solvability rules hold, checked independently") {
  for (const World& w : suite()) {
    CAPTURE(w.name);
    const auto sv = polyline_arc_lengths(w.reference_line);
    const double lw = w.road.lane_width;
    const double ego_front = w.ego.wheelbase + 0.5 * (w.ego.length - w.ego.wheelbase);
    const double stop = w.ego.v * w.ego.v / (2.0 * 3.0) + 10.0;
    const double duration = w.duration.value_or(12.0);

    struct Sl { double s0, s1, l0, l1; };
    std::vector<Sl> statics;
    for (const auto& o : w.static_obstacles) {
      Sl e{1e9, -1e9, 1e9, -1e9};
      for (const Point2& p : box_points(obstacle_box(o))) {
        const PolylineProjection q = project_to_polyline(w.reference_line, p.x, p.y);
        e = {std::min(e.s0, q.s), std::max(e.s1, q.s), std::min(e.l0, q.l), std::max(e.l1, q.l)};
      }
      statics.push_back(e);
      // Nothing static in the ego's lane within the first 40 m, nor closer
      // than a comfortable stop (v^2 / (2 * 3 m/s^2) + 10 m) ahead of the bumper.
      const bool in_ego_lane = e.l1 > -0.5 * lw && e.l0 < 0.5 * lw;
      if (in_ego_lane) {
        CHECK(e.s0 >= 40.0);
        CHECK(e.s0 - ego_front >= stop - 0.2);
      }
    }
    // A lane-width free passage beside the statics at every s.
    for (double s = 0.0; s <= sv.back(); s += 0.5) {
      std::vector<std::pair<double, double>> occ;
      for (const auto& e : statics)
        if (s >= e.s0 && s <= e.s1) occ.emplace_back(e.l0, e.l1);
      std::sort(occ.begin(), occ.end());
      double cursor = w.road.right_boundary.at(s), best = 0.0;
      for (const auto& [a, b] : occ) {
        best = std::max(best, a - cursor);
        cursor = std::max(cursor, b);
      }
      best = std::max(best, w.road.left_boundary.at(s) - cursor);
      CHECK(best >= lw - 0.05);
    }
    // No obstacle on the ego at t = 0 nor within 2 s of constant-speed travel in its lane.
    for (double t = 0.0; t <= 2.0 + 1e-9; t += 0.05) {
      const OrientedBox eb = ego_at(w, sv, t);
      for (const auto& o : w.static_obstacles) CHECK_FALSE(boxes_overlap(eb, obstacle_box(o)));
      for (const auto& d : w.dynamic_obstacles) {
        const auto p = pose_at(d, t);
        if (p) CHECK_FALSE(boxes_overlap(eb, obstacle_box(d, *p)));
      }
    }
    // Dynamic obstacles never hit static ones nor each other.
    for (double t = 0.0; t <= duration + 1e-9; t += 0.05) {
      for (std::size_t i = 0; i < w.dynamic_obstacles.size(); ++i) {
        const auto& d = w.dynamic_obstacles[i];
        const auto p = pose_at(d, t);
        if (!p) continue;
        const OrientedBox b = obstacle_box(d, *p);
        for (const auto& o : w.static_obstacles) CHECK_FALSE(boxes_overlap(b, obstacle_box(o)));
        for (std::size_t k = i + 1; k < w.dynamic_obstacles.size(); ++k) {
          const auto q = pose_at(w.dynamic_obstacles[k], t);
          if (q) CHECK_FALSE(boxes_overlap(b, obstacle_box(w.dynamic_obstacles[k], *q)));
        }
      }
    }
    // Statics do not overlap each other.
    for (std::size_t i = 0; i < w.static_obstacles.size(); ++i)
      for (std::size_t k = i + 1; k < w.static_obstacles.size(); ++k)
        CHECK_FALSE(boxes_overlap(obstacle_box(w.static_obstacles[i]), obstacle_box(w.static_obstacles[k])));
    // Crossing road users: pedestrians (1.0 m box, 1-1.8 m/s, >= 30 m ahead
    // of the ego's front when they appear) and cyclists (1.8 x 0.7 m, 3-5 m/s,
    // >= 40 m), both within 30 deg of perpendicular to the road, on the map.
    for (const auto& d : w.dynamic_obstacles) {
      const bool ped = d.kind == "pedestrian";
      if (!ped && d.kind != "cyclist") continue;
      CHECK(d.length == (ped ? 1.0 : 1.8));
      CHECK(d.width == (ped ? 1.0 : 0.7));
      const auto& first = d.trajectory.front();
      CHECK(first.v >= (ped ? 1.0 : 3.0) - 1e-9);
      CHECK(first.v <= (ped ? 1.8 : 5.0) + 1e-9);
      const PolylineProjection q = project_to_polyline(w.reference_line, first.x, first.y);
      CHECK(std::abs(std::abs(std::remainder(first.heading - q.heading, 2 * std::numbers::pi)) - 0.5 * std::numbers::pi) <=
            (ped ? 23.0 : 33.0) * std::numbers::pi / 180.0);  // + the bend's (1 - kappa l) on the angle
      CHECK(q.s - (ego_front + w.ego.v * first.t) >= (ped ? 30.0 : 40.0));
      CHECK(q.s <= sv.back());
      // It starts off the road and moves across it.
      CHECK((q.l < w.road.right_boundary.at(q.s) || q.l > w.road.left_boundary.at(q.s)));
    }
    // Overtakers start behind the ego, faster than it; a cut-in that brakes
    // ends standing.
    for (const auto& d : w.dynamic_obstacles) {
      if (d.kind == "overtaker") {
        const PolylineProjection q = project_to_polyline(w.reference_line, d.trajectory.front().x, d.trajectory.front().y);
        CHECK(q.s < 0.0);
        CHECK(d.trajectory.front().v > w.ego.v);
      }
      if (d.kind == "cut_in_brake") {
        CHECK(d.trajectory.front().v > 1.0);
        CHECK(d.trajectory.back().v < 0.5 * d.trajectory.front().v);
        double slowest = d.trajectory.front().v;
        for (const auto& p : d.trajectory) slowest = std::min(slowest, p.v);
        CHECK(d.trajectory.back().v <= slowest + 1e-9);  // it ends braking
      }
    }
  }
}
