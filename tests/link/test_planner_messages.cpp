// Scene and Plan codecs at the edges of their number formats: a finite
// double beyond float32's range is refused by the Scene encoder instead of
// arriving as infinity (issue 13, defect 7), while large values float32 can
// hold pass unchanged.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
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

namespace {

// Every field decode_scene writes, compared exactly (bit patterns of NaN aside).
void check_same_scene(const Scene& a, const Scene& b) {
  REQUIRE(a.reference_line.size() == b.reference_line.size());
  for (std::size_t i = 0; i < a.reference_line.size(); ++i) {
    CHECK(a.reference_line[i].x == b.reference_line[i].x);
    CHECK(a.reference_line[i].y == b.reference_line[i].y);
  }
  CHECK(a.road.lane_width == b.road.lane_width);
  CHECK(a.road.target_lane_offset == b.road.target_lane_offset);
  CHECK(a.road.speed_limit == b.road.speed_limit);
  for (const auto* pair : {&a.road.left, &a.road.right}) {
    const auto& other = pair == &a.road.left ? b.road.left : b.road.right;
    CHECK(pair->offset == other.offset);
    REQUIRE(pair->table.size() == other.table.size());
    for (std::size_t i = 0; i < pair->table.size(); ++i) {
      CHECK(pair->table[i].s == other.table[i].s);
      CHECK(pair->table[i].l == other.table[i].l);
    }
  }
  const auto& ea = a.ego;
  const auto& eb = b.ego;
  CHECK(ea.state.x == eb.state.x);
  CHECK(ea.state.y == eb.state.y);
  CHECK(ea.state.heading == eb.state.heading);
  CHECK(ea.state.v == eb.state.v);
  CHECK(ea.state.a == eb.state.a);
  CHECK(ea.state.kappa == eb.state.kappa);
  CHECK(ea.geometry.length == eb.geometry.length);
  CHECK(ea.geometry.width == eb.geometry.width);
  CHECK(ea.geometry.wheelbase == eb.geometry.wheelbase);
  CHECK(ea.limits.a_min == eb.limits.a_min);
  CHECK(ea.limits.a_max == eb.limits.a_max);
  CHECK(ea.limits.lat_acc_max == eb.limits.lat_acc_max);
  CHECK(ea.limits.kappa_max == eb.limits.kappa_max);
  REQUIRE(a.static_obstacles.size() == b.static_obstacles.size());
  for (std::size_t i = 0; i < a.static_obstacles.size(); ++i) {
    const auto& oa = a.static_obstacles[i];
    const auto& ob = b.static_obstacles[i];
    CHECK(oa.id == ob.id);
    CHECK(oa.x == ob.x);
    CHECK(oa.y == ob.y);
    CHECK(oa.heading == ob.heading);
    CHECK(oa.length == ob.length);
    CHECK(oa.width == ob.width);
  }
  REQUIRE(a.dynamic_obstacles.size() == b.dynamic_obstacles.size());
  for (std::size_t i = 0; i < a.dynamic_obstacles.size(); ++i) {
    const auto& oa = a.dynamic_obstacles[i];
    const auto& ob = b.dynamic_obstacles[i];
    CHECK(oa.id == ob.id);
    CHECK(oa.length == ob.length);
    CHECK(oa.width == ob.width);
    REQUIRE(oa.trajectory.size() == ob.trajectory.size());
    for (std::size_t k = 0; k < oa.trajectory.size(); ++k) {
      CHECK(oa.trajectory[k].t == ob.trajectory[k].t);
      CHECK(oa.trajectory[k].x == ob.trajectory[k].x);
      CHECK(oa.trajectory[k].y == ob.trajectory[k].y);
      CHECK(oa.trajectory[k].heading == ob.trajectory[k].heading);
      CHECK(oa.trajectory[k].v == ob.trajectory[k].v);
    }
  }
}

}  // namespace

TEST_CASE("a rejected plan encodes as an empty plan with status invalid_input and its reason") {
  using itp::scene::ValidationReason;
  for (ValidationReason why : {ValidationReason::kNone, ValidationReason::kReferenceLineSharpTurn}) {
    itp::link::PlanHeader h;
    h.cycle = 77;
    h.scene_crc = 0xDEADBEEFu;
    auto plan = std::make_unique<itp::planner::Plan>();
    plan->status = itp::PlanStatus::kInvalidInput;
    plan->invalid = why;
    std::vector<std::uint8_t> a(itp::link::kMaxPlanBytes<itp::DefaultConfig>, 0x11);
    std::vector<std::uint8_t> b(a.size(), 0x22);
    const std::size_t na = itp::link::encode_plan(h, *plan, a);
    const std::size_t nb = itp::link::encode_rejected_plan(h, why, b);
    REQUIRE(na > 0);
    REQUIRE(nb == na);
    CHECK(std::equal(a.begin(), a.begin() + static_cast<long>(na), b.begin()));
    itp::link::PlanHeader back_h;
    auto back = std::make_unique<itp::planner::Plan>();
    REQUIRE(itp::link::decode_plan(std::span<const std::uint8_t>(b.data(), nb), back_h, *back));
    CHECK(back->status == itp::PlanStatus::kInvalidInput);
    CHECK(back->invalid == why);
    CHECK(back->trajectory.empty());
    CHECK(back_h.cycle == 77);
  }
}

TEST_CASE("BasicScene::reset gives a default scene, in place") {
  auto s = std::make_unique<Scene>(scene_test::baseline_scene());
  (void)s->road.left.table.push_back({Scalar(1), Scalar(2)});
  s->road.lane_width = Scalar(3.0);
  s->road.speed_limit = Scalar(30);
  s->ego.geometry.length = Scalar(9);
  s->ego.limits.a_min = Scalar(-2);
  s->reset();
  const auto fresh = std::make_unique<Scene>();
  check_same_scene(*s, *fresh);
}

TEST_CASE("decode_scene into a scene that held another gives the same scene as into a fresh one") {
  // The firmware decodes every cycle into the same scene (cleared in place,
  // not by assigning a temporary): nothing of the previous scene may remain.
  auto big = std::make_unique<Scene>(scene_test::baseline_scene());
  (void)big->road.left.table.push_back({Scalar(0), Scalar(2)});
  (void)big->road.left.table.push_back({Scalar(50), Scalar(3)});
  big->road.speed_limit = Scalar(25);
  (void)big->dynamic_obstacles.push_back(big->dynamic_obstacles[0]);
  big->dynamic_obstacles[1].id = 12;
  auto small = std::make_unique<Scene>(scene_test::baseline_scene());
  small->static_obstacles.clear();
  small->dynamic_obstacles[0].trajectory.pop_back();
  std::vector<std::uint8_t> big_body(itp::link::kMaxSceneBytes<itp::DefaultConfig>);
  std::vector<std::uint8_t> small_body(itp::link::kMaxSceneBytes<itp::DefaultConfig>);
  const std::size_t nb = itp::link::encode_scene(itp::link::SceneHeader{1, 0.5, false}, *big, 1, big_body);
  const std::size_t ns = itp::link::encode_scene(itp::link::SceneHeader{2, 0.5, true}, *small, 1, small_body);
  REQUIRE(nb > 0);
  REQUIRE(ns > 0);

  auto reused = std::make_unique<Scene>();
  auto fresh = std::make_unique<Scene>();
  itp::link::SceneHeader h;
  REQUIRE(itp::link::decode_scene(std::span<const std::uint8_t>(big_body.data(), nb), h, *reused));
  REQUIRE(itp::link::decode_scene(std::span<const std::uint8_t>(small_body.data(), ns), h, *reused));
  CHECK(h.cycle == 2);
  CHECK(h.reset);
  REQUIRE(itp::link::decode_scene(std::span<const std::uint8_t>(small_body.data(), ns), h, *fresh));
  check_same_scene(*reused, *fresh);
  CHECK(reused->static_obstacles.empty());
  CHECK(reused->road.left.table.empty() == small->road.left.table.empty());

  // And the re-encoded bytes are the message that was sent.
  std::vector<std::uint8_t> again(itp::link::kMaxSceneBytes<itp::DefaultConfig>);
  const std::size_t na = itp::link::encode_scene(itp::link::SceneHeader{2, 0.5, true}, *reused, 1, again);
  REQUIRE(na == ns);
  CHECK(std::equal(again.begin(), again.begin() + static_cast<std::ptrdiff_t>(na), small_body.begin()));
}
