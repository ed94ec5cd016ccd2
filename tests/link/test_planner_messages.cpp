// Scene and Plan codecs at the edges of their number formats: a finite
// double beyond float32's range is refused by the Scene encoder instead of
// arriving as infinity (issue 13, defect 7), while large values float32 can
// hold pass unchanged.
#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "../scene/scene_builders.hpp"
#include "itp/link/planner_messages.hpp"

using itp::Scalar;
using itp::scene::Scene;

namespace {

std::size_t encode(const Scene& s, double now = 0.0) {
  std::vector<std::uint8_t> body(itp::link::kMaxSceneBytes<itp::DefaultConfig>);
  return itp::link::encode_scene(itp::link::SceneHeader{1, now, false}, s, 1, body);
}

}  // namespace

TEST_CASE("the Scene encoder refuses a finite value beyond float32 range, never sends it as infinity") {
  const std::vector<std::pair<const char*, std::function<void(Scene&)>>> mutations = {
      {"ego heading 1e300", [](Scene& s) { s.ego.state.heading = Scalar(1e300); }},
      {"ego x 1e300", [](Scene& s) { s.ego.state.x = Scalar(1e300); }},
      {"obstacle length -1e300", [](Scene& s) { s.static_obstacles[0].length = Scalar(-1e300); }},
      {"speed limit 1e39", [](Scene& s) { s.road.speed_limit = Scalar(1e39); }},
      {"prediction t 1e300", [](Scene& s) { s.dynamic_obstacles[0].trajectory[1].t = Scalar(1e300); }},
      {"boundary 1e300", [](Scene& s) { s.road.left.offset = Scalar(1e300); }},
  };
  auto s = std::make_unique<Scene>(scene_test::baseline_scene());
  REQUIRE(encode(*s) > 0);
  for (const auto& [name, mutate] : mutations) {
    *s = scene_test::baseline_scene();
    mutate(*s);
    CHECK_MESSAGE(encode(*s) == 0, name);
  }
  // A scene time far from the predictions: t - now beyond float range.
  *s = scene_test::baseline_scene();
  CHECK(encode(*s, 1e300) == 0);
}

TEST_CASE("values float32 can hold, NaN and infinities travel as they are (the firmware judges them)") {
  auto s = std::make_unique<Scene>(scene_test::baseline_scene());
  s->ego.state.heading = Scalar(1e30);
  s->static_obstacles[0].width = std::numeric_limits<Scalar>::quiet_NaN();
  s->road.speed_limit = std::numeric_limits<Scalar>::infinity();
  std::vector<std::uint8_t> body(itp::link::kMaxSceneBytes<itp::DefaultConfig>);
  const std::size_t n = itp::link::encode_scene(itp::link::SceneHeader{1, 0.0, false}, *s, 1, body);
  REQUIRE(n > 0);
  auto back = std::make_unique<Scene>();
  itp::link::SceneHeader h;
  REQUIRE(itp::link::decode_scene(std::span<const std::uint8_t>(body.data(), n), h, *back));
  CHECK(back->ego.state.heading == doctest::Approx(1e30).epsilon(1e-6));
  CHECK(std::isnan(back->static_obstacles[0].width));
  CHECK(std::isinf(back->road.speed_limit));
}
