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

template <class Cfg>
BasicInprocEndpoint<Cfg>::BasicInprocEndpoint() : planner_(std::make_unique<Planner>()) {
  planner_->set_tick_source(itp::TickSource{&steady_ns, 1000000000u});
}

// Planner::reset() forgets the previous plan and the QPs' hot-start state, so
// every scene is independent of the order of the suite: `--scene X` and the
// same scene inside a suite agree (the firmware targets do the same on the
// Scene message's reset flag).
template <class Cfg>
void BasicInprocEndpoint<Cfg>::reset() {
  planner_->reset();
}

template <class Cfg>
EndpointResult BasicInprocEndpoint<Cfg>::plan(const itp::scene::BasicScene<Cfg>& scene, double now,
                                              itp::planner::BasicPlan<Cfg>& out) {
  planner_->plan(itp::planner::BasicPlanRequest<Cfg>{&scene, now}, out);
  EndpointResult r;
  r.ok = true;
  if (out.timing.tick_hz > 0) {
    r.cycle_time_us = static_cast<double>(out.timing.total) * 1e6 / static_cast<double>(out.timing.tick_hz);
  }
  return r;
}

#define HIL_SIM_INSTANTIATE_INPROC(Cfg) template class BasicInprocEndpoint<Cfg>;
HIL_SIM_FOR_EACH_CONFIG(HIL_SIM_INSTANTIATE_INPROC)
#undef HIL_SIM_INSTANTIATE_INPROC

}  // namespace hil::sim
