#pragma once
// What a World read from a file must survive (scene/1 and CommonRoad
// targets): conversion to the planner's Scene at its start, validation, and
// the Scene codec (encoded unless a value is beyond float32, then decoded).
#include <cstdint>
#include <memory>
#include <vector>

#include "itp/link/planner_messages.hpp"
#include "itp/scene/validation.hpp"
#include "sim/scene_convert.hpp"
#include "sim/world.hpp"

namespace fuzz {

inline void trap_unless(bool ok) {
  if (!ok) __builtin_trap();
}

inline void check_world(const hil::sim::World& w) {
  static auto scene = std::make_unique<itp::scene::Scene>();
  static auto back = std::make_unique<itp::scene::Scene>();
  static std::vector<std::uint8_t> body(itp::link::kMaxSceneBytes<itp::DefaultConfig>);
  if (w.reference_line.empty()) return;
  const hil::sim::ConvertResult conv =
      hil::sim::make_planner_scene(w, hil::sim::ego_at_start(w), 0.0, hil::sim::Prediction::kConstantVelocity, *scene);
  if (!conv.ok) return;
  static_cast<void>(itp::scene::validate(*scene, 0.0));
  const std::size_t n = itp::link::encode_scene(itp::link::SceneHeader{1, 0.0, true}, *scene, 1, body);
  if (n == 0) return;  // a value beyond float32: refused, as documented
  itp::link::SceneHeader h;
  trap_unless(itp::link::decode_scene(std::span<const std::uint8_t>(body.data(), n), h, *back));
  trap_unless(back->reference_line.size() == scene->reference_line.size() &&
              back->static_obstacles.size() == scene->static_obstacles.size() &&
              back->dynamic_obstacles.size() == scene->dynamic_obstacles.size());
}

}  // namespace fuzz
