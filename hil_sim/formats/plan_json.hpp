#pragma once
// plan/1 (../shared/design/FORMATS.md): what the planner returned for one scene.
#include <nlohmann/json.hpp>

#include "itp/planner/plan.hpp"

namespace hil::formats {

// `plan/1` JSON: status (+ reason), iterations, decisions, the trajectory and
// timing_us (null entries when the firmware had no counter).
// Compiled for every configuration of ITP_FOR_EACH_CONFIG.
template <class Cfg>
nlohmann::json plan_to_json(const itp::planner::BasicPlan<Cfg>& plan);

const char* lateral_name(itp::planner::LateralSide side);

}  // namespace hil::formats
