#pragma once
// The `inproc` target: the planner called directly in this process, timed with
// the host's steady clock. Deterministic: identical inputs give identical plans.
#include <memory>
#include <string>

#include "itp/planner/planner.hpp"
#include "sim/planner_endpoint.hpp"

namespace hil::sim {

// Compiled for HIL_SIM_FOR_EACH_CONFIG (inproc_endpoint.cpp).
template <class Cfg>
class BasicInprocEndpoint final : public BasicPlannerEndpoint<Cfg> {
 public:
  using Planner = itp::planner::BasicPlanner<Cfg>;
  BasicInprocEndpoint();
  void reset() override;  // Planner::reset(): no plan, no QP hot-start state from the last scene
  EndpointResult plan(const itp::scene::BasicScene<Cfg>& scene, double now, itp::planner::BasicPlan<Cfg>& out) override;
  std::string name() const override { return "inproc"; }

  // The planner itself (settings, the last cycle's stages for plots).
  Planner& planner() { return *planner_; }
  const Planner& planner() const { return *planner_; }

 private:
  std::unique_ptr<Planner> planner_;  // 0.4-0.6 MB: never on the stack
};

using InprocEndpoint = BasicInprocEndpoint<itp::DefaultConfig>;

}  // namespace hil::sim
