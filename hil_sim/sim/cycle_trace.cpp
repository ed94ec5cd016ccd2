#include "sim/cycle_trace.hpp"

#include <optional>

#include <nlohmann/json.hpp>

#include "itp/core/status.hpp"

namespace hil::sim {
namespace {

using nlohmann::json;

// itp::PlanStatus's names (plan/1), and "link_error" when no plan came back.
const char* status_name(const std::optional<itp::PlanStatus>& s) { return s ? itp::to_string(*s) : "link_error"; }

}  // namespace

void write_cycle_trace(std::ostream& out, const std::string& scene, const SceneRunResult& r) {
  for (std::size_t k = 0; k < r.cycles.size(); ++k) {
    const CycleRecord& c = r.cycles[k];
    json j{{"scene", scene}, {"t", c.t}, {"status", status_name(c.status)}, {"reason", c.reason},
           {"iterations", c.iterations}, {"v", c.v}, {"v_plan", c.v_plan}, {"a_lon", c.a_lon},
           {"a_lat", c.a_lat}, {"collision", c.collision}};
    if (c.path_deviation >= 0) {
      j["path_deviation"] = c.path_deviation;
      j["path_deviation_t"] = c.path_deviation_t;
    }
    j["decisions"] = c.decisions;
    if (!c.collision_with.empty()) j["collision_with"] = c.collision_with;
    if (c.left_out > 0) j["obstacles_left_out"] = c.left_out;
    if (c.reference_deviation_m > 0) j["reference_deviation_m"] = c.reference_deviation_m;
    if (c.boundary_narrowing_m > 0) j["boundary_narrowing_m"] = c.boundary_narrowing_m;
    if (c.stop_wall_lane) j["stop_wall_lane"] = *c.stop_wall_lane;
    j["clearance"] = c.clearance ? json(*c.clearance) : json(nullptr);
    if (k < r.trace.size()) {
      j["x"] = r.trace[k].pose.x;
      j["y"] = r.trace[k].pose.y;
      j["heading"] = r.trace[k].pose.heading;
    }
    if (c.cycle_time_us >= 0) j["cycle_time_us"] = c.cycle_time_us;
    if (c.instructions >= 0) j["instructions"] = c.instructions;
    if (c.work) {
      const itp::planner::StageTiming& w = *c.work;
      j["work"] = json{{"tick_hz", w.tick_hz},
                       {"prepare", w.prepare},
                       {"decision", w.decision},
                       {"coarse", w.coarse},
                       {"path", w.path},
                       {"speed", w.speed},
                       {"check", w.check},
                       {"total", w.total},
                       {"decision_runs", w.decision_runs},
                       {"tree_nodes", w.tree_nodes},
                       {"coarse_qps", w.coarse_qps},
                       {"coarse_iterations", w.coarse_iterations},
                       {"path_solves", w.path_solves},
                       {"path_iterations", w.path_iterations},
                       {"speed_solves", w.speed_solves},
                       {"speed_iterations", w.speed_iterations}};
    }
    out << j.dump() << '\n';
  }
}

}  // namespace hil::sim
