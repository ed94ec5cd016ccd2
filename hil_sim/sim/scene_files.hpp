#pragma once
// The one place where the tools load a scene file: scene/1 JSON, or a
// CommonRoad XML scenario imported on the fly (docs/commonroad.md). The kind
// is told by the extension (.xml / .json), else by the first character of the
// content ('<' is XML).
#include <optional>
#include <string>
#include <vector>

#include "sim/commonroad_world.hpp"
#include "sim/world.hpp"

namespace hil::sim {

enum class SceneFileKind { kSceneJson, kCommonRoadXml };

struct LoadedScene {
  std::optional<World> world;
  std::string error;               // "FILE: what" on failure
  std::vector<std::string> notes;  // the import's notes (CommonRoad)
  SceneFileKind kind = SceneFileKind::kSceneJson;
  explicit operator bool() const { return world.has_value(); }
};

SceneFileKind scene_file_kind(const std::string& path, const std::string& content);

// Never throws. A world without a name is named after the file.
LoadedScene load_scene(const std::string& path, const CommonRoadOptions& commonroad = {});

}  // namespace hil::sim
