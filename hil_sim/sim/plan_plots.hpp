#pragma once
// Pictures of one planning cycle, for people: the SL view (road, obstacle
// boxes, convex zones, the chosen corridor, coarse samples, the path), the XY
// view (road, obstacles, the ego's footprints along the trajectory) and the ST
// view (conflict zones of the dynamic obstacles, the speed QP's bounds, s(t)).
#include <string>
#include <vector>

#include "itp/planner/planner.hpp"
#include "itp/scene/scene.hpp"
#include "sim/sim_config.hpp"

namespace hil::sim {

// Templates on the planner configuration, compiled for HIL_SIM_FOR_EACH_CONFIG.
template <class Cfg>
std::string plot_sl(const itp::planner::BasicPlanner<Cfg>& planner, const itp::scene::BasicScene<Cfg>& scene,
                    const std::string& title);
// `now`: the scene time the plan was made at (obstacles are drawn at now + t).
template <class Cfg>
std::string plot_xy(const itp::planner::BasicPlanner<Cfg>& planner, const itp::scene::BasicScene<Cfg>& scene,
                    const itp::planner::BasicPlan<Cfg>& plan, double now, const std::string& title);
template <class Cfg>
std::string plot_st(const itp::planner::BasicPlanner<Cfg>& planner, const itp::planner::BasicPlan<Cfg>& plan,
                    const std::string& title);

// Several SVG documents stacked vertically into one.
std::string stack_svgs(const std::vector<std::string>& svgs);

}  // namespace hil::sim
