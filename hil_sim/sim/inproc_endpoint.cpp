#include "sim/inproc_endpoint.hpp"

#include <chrono>
#include <cstdint>

namespace hil::sim {
namespace {

std::uint64_t steady_ns() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
          .count());
}

}  // namespace

InprocEndpoint::InprocEndpoint() : planner_(std::make_unique<itp::planner::Planner>()) {
  planner_->set_tick_source(itp::TickSource{&steady_ns, 1000000000u});
}

// Planner::reset() forgets the previous plan, but the path, speed and coarse
// QPs keep their factorisation and last active set (hot starts), so the first
// cycles of a scene would depend on the scene run before it (different QP
// iterations, results differing in the last bits, then diverging in closed
// loop). A fresh planner (same settings) makes every scene independent of the
// order of the suite: `--scene X` and the same scene inside a suite agree.
void InprocEndpoint::reset() {
  planner_->reset();
  const itp::planner::PlannerSettings settings = planner_->settings();
  planner_ = std::make_unique<itp::planner::Planner>();
  planner_->settings() = settings;
  planner_->set_tick_source(itp::TickSource{&steady_ns, 1000000000u});
}

EndpointResult InprocEndpoint::plan(const itp::scene::Scene& scene, double now, itp::planner::Plan& out) {
  planner_->plan(itp::planner::PlanRequest{&scene, now}, out);
  EndpointResult r;
  r.ok = true;
  if (out.timing.tick_hz > 0) {
    r.cycle_time_us = static_cast<double>(out.timing.total) * 1e6 / static_cast<double>(out.timing.tick_hz);
  }
  return r;
}

}  // namespace hil::sim
