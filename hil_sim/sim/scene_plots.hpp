#pragma once
// Pictures of one closed-loop scene run, for people: the per-scene SVG and
// its row in the plots' index.html (`hil_sim run --plots`).
#include <string>

#include "sim/closed_loop.hpp"
#include "sim/svg.hpp"
#include "sim/world.hpp"

namespace hil::sim {

// The per-scene SVG: the XY view of the run (ego footprints over time and the
// obstacles), speed, clearance, accelerations and plan status over time, and
// for each snapshot the SL / XY / ST views of that cycle re-planned in-process.
std::string scene_run_svg(const World& world, const SceneRunResult& result);

// The scene's row in index.html: outcome highlight, a link to `svg_file`, and
// its metrics (collision, departure, fallbacks, clearance, comfort, tags).
svg::IndexRow scene_index_row(const World& world, const SceneSummary& summary, const std::string& svg_file);

}  // namespace hil::sim
