// libFuzzer target: the scene/1 reader (hil_sim/sim/world.cpp). It must
// never throw or crash; a scene it accepts must write back as scene/1 that
// reads to the same text again (a fixed point after one round), and survive
// conversion, validation and the Scene codec (scene_checks.hpp).
#include <string>

#include "scene_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const hil::sim::SceneParseResult r = hil::sim::parse_scene_text(text);
  if (!r) {
    fuzz::trap_unless(!r.error.empty());
    return 0;
  }
  const std::string once = hil::sim::scene_to_text(*r.world);
  const hil::sim::SceneParseResult again = hil::sim::parse_scene_text(once);
  fuzz::trap_unless(static_cast<bool>(again));
  fuzz::trap_unless(hil::sim::scene_to_text(*again.world) == once);
  fuzz::check_world(*r.world);
  return 0;
}
