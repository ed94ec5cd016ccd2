#include "formats/plan_json.hpp"

#include "itp/configurations.hpp"

namespace hil::formats {

const char* lateral_name(itp::planner::LateralSide side) {
  switch (side) {
    case itp::planner::LateralSide::kLeft: return "left";
    case itp::planner::LateralSide::kRight: return "right";
    case itp::planner::LateralSide::kNone: return "none";
  }
  return "none";
}

template <class Cfg>
nlohmann::json plan_to_json(const itp::planner::BasicPlan<Cfg>& plan) {
  using nlohmann::json;
  json j;
  j["format"] = "plan/1";
  j["status"] = itp::to_string(plan.status);
  if (plan.status == itp::PlanStatus::kFallback) {
    j["reason"] = itp::planner::to_string(plan.fallback);
    if (plan.fallback == itp::planner::FallbackReason::kCollision && plan.collision_obstacle >= 0) {
      // Optional plan/1 extension (docs/planner.md): what the rejected trajectory met.
      j["collision"] = {{"obstacle", plan.collision_obstacle}, {"t", plan.collision_time}};
    }
  } else if (plan.status == itp::PlanStatus::kInvalidInput) {
    j["reason"] = itp::scene::to_string(plan.invalid);
  }
  j["iterations"] = plan.iterations;
  json decisions = json::array();
  for (const auto& d : plan.decisions) {
    if (d.lateral != itp::planner::LateralSide::kNone) {
      decisions.push_back({{"obstacle", d.obstacle}, {"lateral", lateral_name(d.lateral)}});
    }
    if (d.dynamic && d.longitudinal != itp::speed::Longitudinal::kIgnore) {
      decisions.push_back({{"obstacle", d.obstacle}, {"longitudinal", itp::speed::to_string(d.longitudinal)}});
    }
  }
  j["decision"] = decisions;
  json traj = json::array();
  for (const auto& p : plan.trajectory) {
    traj.push_back({{"t", p.t}, {"x", p.x}, {"y", p.y}, {"heading", p.heading}, {"kappa", p.kappa},
                    {"v", p.v}, {"a", p.a}, {"s", p.s}, {"l", p.l}});
  }
  j["trajectory"] = traj;
  json timing;
  const auto us = [&](std::uint64_t ticks) -> json {
    if (plan.timing.tick_hz == 0) return nullptr;
    return 1e6 * static_cast<double>(ticks) / static_cast<double>(plan.timing.tick_hz);
  };
  timing["total"] = us(plan.timing.total);
  timing["prepare"] = us(plan.timing.prepare);
  timing["decision"] = us(plan.timing.decision);
  timing["path"] = us(plan.timing.path);
  timing["speed"] = us(plan.timing.speed);
  timing["check"] = us(plan.timing.check);
  j["timing_us"] = timing;
  j["qp"] = {{"solves", plan.qp_solves}, {"iterations", plan.qp_iterations}};
  return j;
}

#define HIL_FORMATS_INSTANTIATE_PLAN_JSON(Cfg) \
  template nlohmann::json plan_to_json<Cfg>(const itp::planner::BasicPlan<Cfg>&);
ITP_FOR_EACH_CONFIG(HIL_FORMATS_INSTANTIATE_PLAN_JSON)
#undef HIL_FORMATS_INSTANTIATE_PLAN_JSON

}  // namespace hil::formats
