#pragma once
// The `inproc` target: the planner called directly in this process, timed with
// the host's steady clock. Deterministic: identical inputs give identical plans.
#include <memory>
#include <string>

#include "itp/planner/planner.hpp"
#include "sim/planner_endpoint.hpp"

namespace hil::sim {

class InprocEndpoint final : public PlannerEndpoint {
 public:
  InprocEndpoint();
  void reset() override;  // Planner::reset(): no plan, no QP hot-start state from the last scene
  EndpointResult plan(const itp::scene::Scene& scene, double now, itp::planner::Plan& out) override;
  std::string name() const override { return "inproc"; }

  // The planner itself (settings, the last cycle's stages for plots).
  itp::planner::Planner& planner() { return *planner_; }
  const itp::planner::Planner& planner() const { return *planner_; }

 private:
  std::unique_ptr<itp::planner::Planner> planner_;  // ~0.5 MB: never on the stack
};

}  // namespace hil::sim
