#pragma once
// CommonRoad scenario -> the simulator's World (scene/1): `hil_sim import` and
// `hil_sim run --scene FILE.xml`. What is mapped and how, the defaults and
// the errors: docs/commonroad.md. import_commonroad() never throws: malformed
// or unsupported content is an error naming the element (and its line).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "formats/commonroad.hpp"
#include "sim/world.hpp"

namespace hil::sim {

// Defaults where a CommonRoad file says nothing (docs/commonroad.md).
// The ego: CommonRoad's vehicle type 2 (BMW 320i), the parameter set of its
// vehicle models; planning problems do not give a size.
inline constexpr double kCommonRoadEgoLength = 4.508;     // [m]
inline constexpr double kCommonRoadEgoWidth = 1.610;      // [m]
inline constexpr double kCommonRoadEgoWheelbase = 2.579;  // [m] a + b = 1.156 + 1.422
// No max-speed sign on the route: 50 km/h, raised to the fastest initial speed
// of the ego and the dynamic obstacles (a limit below them would brake for no sign).
inline constexpr double kCommonRoadDefaultSpeedLimit = 50.0 / 3.6;  // [m/s]
inline constexpr double kCommonRoadDefaultDuration = 20.0;          // [s] no goal time, no trajectories
inline constexpr double kCommonRoadMaxDuration = 60.0;              // [s] cap on the scenario's own length

struct CommonRoadOptions {
  std::optional<long> planning_problem;  // id; default the first in the file
  bool opposite_lanes = false;           // the road includes opposite-direction lanes
  std::optional<double> speed_limit;     // [m/s] instead of the signs'
  std::optional<double> duration;        // [s] instead of the scenario's
  bool drop_set_based = false;           // leave set-based obstacles out instead of failing
};

struct CommonRoadImport {
  std::optional<World> world;
  std::string error;               // on failure: names the element (and line)
  std::vector<std::string> notes;  // what was chosen, defaulted or left out
  explicit operator bool() const { return world.has_value(); }
};

// Text of a CommonRoad XML file -> World.
CommonRoadImport import_commonroad(std::string_view xml, const CommonRoadOptions& options = {});
// The same from parsed structs (the reader's output).
CommonRoadImport map_commonroad(const formats::commonroad::Scenario& scenario, const CommonRoadOptions& options);

// Max-speed sign ids across CommonRoad's countries: "274" (Germany and the
// default set), "274.1" (zone), "R2-1" (USA), "r301" (Spain).
bool is_max_speed_sign(const std::string& sign_id);

}  // namespace hil::sim
