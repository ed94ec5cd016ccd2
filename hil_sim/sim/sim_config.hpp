#pragma once
// The planner configurations the simulator plans with (`hil_sim run
// --config`): the default (the paper's envelope: 10 static + 5 dynamic
// objects) and the road ECU's (32 + 32 objects, predictions every 0.2 s over
// 8 s; itp/configurations.hpp). The scene conversion, the endpoints, the
// closed loop and the plan plots are templates on the configuration, compiled
// for each of HIL_SIM_FOR_EACH_CONFIG; `with_config` turns the run-time
// choice into the type once, at the top of a command.
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>

#include "itp/configurations.hpp"
#include "itp/scene/scene.hpp"

// X(config type) for every configuration the simulator can plan with.
#define HIL_SIM_FOR_EACH_CONFIG(X) \
  X(::itp::DefaultConfig)          \
  X(::itp::RoadConfig)

namespace hil::sim {

enum class SimConfig { kDefault, kRoad };

// "default" | "road"; nullopt for any other name.
inline std::optional<SimConfig> parse_sim_config(const std::string& name) {
  if (name == "default") return SimConfig::kDefault;
  if (name == "road") return SimConfig::kRoad;
  return std::nullopt;
}

inline const char* to_string(SimConfig config) { return config == SimConfig::kRoad ? "road" : "default"; }

template <class Cfg>
constexpr SimConfig sim_config_of() {
  static_assert(std::is_same_v<Cfg, itp::DefaultConfig> || std::is_same_v<Cfg, itp::RoadConfig>,
                "not a configuration the simulator is compiled for (HIL_SIM_FOR_EACH_CONFIG)");
  return std::is_same_v<Cfg, itp::RoadConfig> ? SimConfig::kRoad : SimConfig::kDefault;
}

// Calls f(std::type_identity<Cfg>{}) with the configuration `config` names.
template <class F>
decltype(auto) with_config(SimConfig config, F&& f) {
  if (config == SimConfig::kRoad) return f(std::type_identity<itp::RoadConfig>{});
  return f(std::type_identity<itp::DefaultConfig>{});
}

// A planner Scene of any of these configurations, shared (the closed loop's
// snapshots, which the plots re-plan with the same configuration).
template <class Cfg>
using SceneRef = std::shared_ptr<const itp::scene::BasicScene<Cfg>>;
using AnySceneRef = std::variant<SceneRef<itp::DefaultConfig>, SceneRef<itp::RoadConfig>>;

}  // namespace hil::sim
