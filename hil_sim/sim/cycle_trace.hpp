#pragma once
// The per-cycle trace of a closed-loop run (`hil_sim run --trace`): JSON
// Lines, one object per planning cycle. Keys: docs/simulation.md.
#include <ostream>
#include <string>

#include "sim/closed_loop.hpp"

namespace hil::sim {

// Appends one JSON object per cycle of `result`: what the planner said
// (status, reason, decisions) and where the ego was.
void write_cycle_trace(std::ostream& out, const std::string& scene, const SceneRunResult& result);

}  // namespace hil::sim
