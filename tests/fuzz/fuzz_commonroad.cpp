// libFuzzer target: the CommonRoad importer (the pugixml reader in
// hil_sim/formats/commonroad_reader.cpp and the mapping to a World in
// hil_sim/sim/commonroad_*). It must never throw or crash: a refusal names
// what is wrong, and a World it returns survives conversion, validation and
// the Scene codec (scene_checks.hpp).
#include <string_view>

#include "scene_checks.hpp"
#include "sim/commonroad_world.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view xml(reinterpret_cast<const char*>(data), size);
  hil::sim::CommonRoadOptions options;
  options.drop_set_based = size % 2 == 0;  // both ways of treating set-based obstacles
  const hil::sim::CommonRoadImport r = hil::sim::import_commonroad(xml, options);
  if (!r) {
    fuzz::trap_unless(!r.error.empty());
    return 0;
  }
  fuzz::check_world(*r.world);
  return 0;
}
