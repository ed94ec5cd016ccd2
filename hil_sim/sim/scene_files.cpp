#include "sim/scene_files.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

namespace hil::sim {

SceneFileKind scene_file_kind(const std::string& path, const std::string& content) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".xml" || ext == ".XML") return SceneFileKind::kCommonRoadXml;
  if (ext == ".json") return SceneFileKind::kSceneJson;
  std::size_t i = content.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;  // UTF-8 byte order mark
  while (i < content.size() && (content[i] == ' ' || content[i] == '\t' || content[i] == '\r' || content[i] == '\n')) ++i;
  return i < content.size() && content[i] == '<' ? SceneFileKind::kCommonRoadXml : SceneFileKind::kSceneJson;
}

LoadedScene load_scene(const std::string& path, const CommonRoadOptions& commonroad) {
  LoadedScene out;
  try {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      out.error = fmt::format("{}: cannot open the file", path);
      return out;
    }
    std::ostringstream ss;
    ss << in.rdbuf();
    const std::string content = ss.str();
    out.kind = scene_file_kind(path, content);
    if (out.kind == SceneFileKind::kCommonRoadXml) {
      CommonRoadImport imported = import_commonroad(content, commonroad);
      out.notes = std::move(imported.notes);
      if (!imported) {
        out.error = fmt::format("{}: CommonRoad: {}", path, imported.error);
        return out;
      }
      out.world = std::move(imported.world);
    } else {
      SceneParseResult parsed = parse_scene_text(content);
      if (!parsed) {
        out.error = fmt::format("{}: {}", path, parsed.error);
        return out;
      }
      out.world = std::move(parsed.world);
    }
    if (out.world->name.empty()) out.world->name = std::filesystem::path(path).stem().string();
  } catch (const std::exception& e) {
    out.world.reset();
    out.error = fmt::format("{}: {}", path, e.what());
  }
  return out;
}

}  // namespace hil::sim
