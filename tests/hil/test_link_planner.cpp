#include <doctest/doctest.h>

#include <type_traits>

#include <cmath>
#include <memory>
#include <vector>

#include "itp/link/planner_messages.hpp"
#include "itp/planner/planner.hpp"
#include "sim/link_endpoint.hpp"
#include "sim/scene_convert.hpp"
#include "sim/scene_generator.hpp"

using namespace hil::sim;

TEST_CASE("Scene and Plan messages round-trip within float precision") {
  const World w = generate_scene(7, 3);
  auto scene = std::make_unique<itp::scene::Scene>();
  REQUIRE(make_planner_scene(w, ego_at_start(w), 1.0, Prediction::kGroundTruth, *scene).ok);
  std::vector<std::uint8_t> body(itp::link::kMaxSceneBytes<itp::DefaultConfig>);
  itp::link::SceneHeader h{42, 1.0, true};
  const std::size_t n = itp::link::encode_scene(h, *scene, 1, body);
  REQUIRE(n > 0);
  auto back = std::make_unique<itp::scene::Scene>();
  itp::link::SceneHeader hb;
  REQUIRE(itp::link::decode_scene(std::span<const std::uint8_t>(body.data(), n), hb, *back));
  CHECK(hb.cycle == 42);
  CHECK(hb.reset);
  CHECK(hb.now == 1.0);
  REQUIRE(back->reference_line.size() == scene->reference_line.size());
  for (std::size_t i = 0; i < scene->reference_line.size(); ++i) {
    CHECK(back->reference_line[i].x == doctest::Approx(scene->reference_line[i].x).epsilon(1e-6));
  }
  REQUIRE(back->dynamic_obstacles.size() == scene->dynamic_obstacles.size());
  for (std::size_t i = 0; i < scene->dynamic_obstacles.size(); ++i) {
    const auto& a = scene->dynamic_obstacles[i].trajectory;
    const auto& b = back->dynamic_obstacles[i].trajectory;
    REQUIRE(a.size() == b.size());
    CHECK(b.back().t == doctest::Approx(a.back().t).epsilon(1e-6));
    CHECK(b.back().x == doctest::Approx(a.back().x).epsilon(1e-6));
  }
  CHECK(back->ego.state.v == doctest::Approx(scene->ego.state.v));
  // Thinned predictions keep the first and last samples.
  const std::size_t m = itp::link::encode_scene(h, *scene, 5, body);
  REQUIRE(itp::link::decode_scene(std::span<const std::uint8_t>(body.data(), m), hb, *back));
  if (!scene->dynamic_obstacles.empty()) {
    CHECK(back->dynamic_obstacles[0].trajectory.back().t ==
          doctest::Approx(scene->dynamic_obstacles[0].trajectory.back().t).epsilon(1e-6));
    CHECK(back->dynamic_obstacles[0].trajectory.size() < scene->dynamic_obstacles[0].trajectory.size());
  }
  // Malformed bodies are rejected, never crash.
  CHECK_FALSE(itp::link::decode_scene(std::span<const std::uint8_t>(body.data(), m / 2), hb, *back));
}

TEST_CASE_TEMPLATE("a scene and a plan filled to capacity encode to the computed maximum sizes", Cfg,
                   itp::DefaultConfig, itp::RoadConfig) {
  auto scene = std::make_unique<itp::scene::BasicScene<Cfg>>();
  while (scene->reference_line.push_back({static_cast<double>(scene->reference_line.size()), 0})) {
  }
  for (auto* b : {&scene->road.left, &scene->road.right}) {
    while (b->table.push_back({static_cast<double>(b->table.size()), 2.0})) {
    }
  }
  while (scene->static_obstacles.push_back({})) {
  }
  while (scene->dynamic_obstacles.push_back({})) {
  }
  for (auto& o : scene->dynamic_obstacles) {
    while (o.trajectory.push_back({})) {
    }
  }
  std::vector<std::uint8_t> body(itp::link::kMaxSceneBytes<Cfg>);
  CHECK(itp::link::encode_scene({}, *scene, 1, body) == itp::link::kMaxSceneBytes<Cfg>);
  auto plan = std::make_unique<itp::planner::BasicPlan<Cfg>>();
  while (plan->trajectory.push_back({})) {
  }
  while (plan->decisions.push_back({})) {
  }
  CHECK(itp::link::encode_plan(itp::link::PlanHeader{}, *plan, body) == itp::link::kMaxPlanBytes<Cfg>);
  // One secured message holds the largest of either (checked at compile time as well).
  CHECK(itp::link::kMaxSceneBytes<Cfg> + itp::link::kSecuredOverhead <= itp::link::kMaxMessageBytes);
  // docs/protocol.md states these sizes.
  if constexpr (std::is_same_v<Cfg, itp::RoadConfig>) {
    CHECK(itp::link::kMaxSceneBytes<Cfg> == 28426);
    CHECK(itp::link::kMaxPlanBytes<Cfg> == 3128);
  } else {
    CHECK(itp::link::kMaxSceneBytes<Cfg> == 9947);
    CHECK(itp::link::kMaxPlanBytes<Cfg> == 2785);
  }
  // At the smallest segment size the host shrinks to (32 bytes) the sealed
  // Scene would need more than 255 segments: the sender takes larger ones
  // (the fewest that fit 255), which the receiver accepts (<= 1024 bytes).
  const std::size_t sealed = itp::link::kMaxSceneBytes<Cfg> + itp::link::kSecuredOverhead;
  const std::size_t fewest = (sealed + itp::link::kMaxSegments - 1) / itp::link::kMaxSegments;
  CHECK(fewest <= itp::link::kMaxSegmentBytes);
}

// The road image (RoadConfig) gets 20 more cars on a parallel road 40 m to
// the left, in range: up to 35 objects, a Scene of up to 20 KB (20 segments).
TEST_CASE_TEMPLATE("the host-port firmware plans generated scenes like the in-process planner", Cfg, itp::DefaultConfig,
                   itp::RoadConfig) {
  constexpr bool kRoad = std::is_same_v<Cfg, itp::RoadConfig>;
  std::string error;
  auto endpoint = make_link_endpoint<Cfg>("host", "", &error);
  REQUIRE_MESSAGE(endpoint != nullptr, error);
  auto planner = std::make_unique<itp::planner::BasicPlanner<Cfg>>();
  auto local = std::make_unique<itp::planner::BasicPlan<Cfg>>();
  auto remote = std::make_unique<itp::planner::BasicPlan<Cfg>>();
  auto scene = std::make_unique<itp::scene::BasicScene<Cfg>>();
  int compared = 0;
  for (int i = 0; i < 6; ++i) {
    World w = generate_scene(11, i);
    for (int k = 0; kRoad && k < 20; ++k) {
      DynamicObstacle d;
      d.id = 200 + k;
      d.length = 4.5;
      d.width = 1.8;
      d.trajectory.push_back({0.0, 7.5 * k, 40.0, 0.0, 10.0});
      w.dynamic_obstacles.push_back(d);
    }
    const ConvertResult conv = make_planner_scene(w, ego_at_start(w), 0.0, Prediction::kConstantVelocity, *scene);
    REQUIRE(conv.ok);
    if (kRoad) CHECK(conv.left_out() == 0);
    // The in-process planner gets the scene as the firmware sees it (float on the wire).
    std::vector<std::uint8_t> body(itp::link::kMaxSceneBytes<Cfg>);
    const std::size_t n = itp::link::encode_scene({1, 0.0, true}, *scene, 1, body);
    itp::link::SceneHeader h;
    auto wire = std::make_unique<itp::scene::BasicScene<Cfg>>();
    REQUIRE(itp::link::decode_scene(std::span<const std::uint8_t>(body.data(), n), h, *wire));
    if (kRoad) CHECK(wire->dynamic_obstacles.size() >= 20);  // the parallel road's cars all arrive
    planner->reset();
    planner->plan({wire.get(), 0.0}, *local);
    endpoint->reset();
    const EndpointResult r = endpoint->plan(*scene, 0.0, *remote);
    REQUIRE_MESSAGE(r.ok, r.error);
    CHECK(r.cycle_time_us > 0);
    CHECK(remote->status == local->status);
    CHECK(remote->iterations == local->iterations);
    REQUIRE(remote->trajectory.size() == local->trajectory.size());
    for (std::size_t k = 0; k < local->trajectory.size(); ++k) {
      CHECK(remote->trajectory[k].x == doctest::Approx(local->trajectory[k].x).epsilon(1e-6).scale(1.0));
      CHECK(remote->trajectory[k].v == doctest::Approx(local->trajectory[k].v).epsilon(1e-5).scale(1.0));
    }
    ++compared;
  }
  CHECK(compared == 6);
}
