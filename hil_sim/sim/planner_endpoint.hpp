#pragma once
// What the closed loop talks to: a planner that takes one cycle's Scene and
// returns a Plan. `inproc` calls the planner directly (and, to exercise the
// framing, may pass the bytes through a loopback link); `host` and `qemu`
// send a Scene message over the serial-like link to a firmware and decode
// its Plan message (hil_sim/link/, docs/protocol.md). A class template on the
// planner configuration (sim/sim_config.hpp), like the planner itself:
// PlannerEndpoint is the default configuration's.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "itp/link/messages.hpp"
#include "itp/planner/plan.hpp"
#include "itp/scene/scene.hpp"
#include "sim/sim_config.hpp"

namespace hil::sim {

struct EndpointResult {
  bool ok = false;            // false: timeout, corrupt or missing reply (counted as a link error)
  std::string error;          // for people, when !ok
  bool scene_mismatch = false;  // the firmware planned a Scene other than the one sent (its CRC echo differs)
  double cycle_time_us = -1;  // host targets: the planner's own total time; < 0 when not measured
  double instructions = -1;   // qemu: instructions of the planning cycle (40 per tick); < 0 when not measured
};

template <class Cfg>
class BasicPlannerEndpoint {
 public:
  using Config = Cfg;
  virtual ~BasicPlannerEndpoint() = default;
  // A new scene starts: the planner forgets its previous plan (no stitching across scenes).
  virtual void reset() = 0;
  // Plans one cycle at scene time `now` (the Scene's predictions are in scene time).
  virtual EndpointResult plan(const itp::scene::BasicScene<Cfg>& scene, double now, itp::planner::BasicPlan<Cfg>& out) = 0;
  virtual std::string name() const = 0;  // "inproc", "host", "qemu"
  // The firmware's resource use (Diagnostics message); nullopt when the
  // endpoint has no firmware or it did not answer.
  virtual std::optional<itp::link::Diagnostics> diagnostics() { return std::nullopt; }
  // What the link counted over the run (report/1 key "link"); null without a link.
  virtual nlohmann::json link_statistics() const { return nullptr; }
};

using PlannerEndpoint = BasicPlannerEndpoint<itp::DefaultConfig>;

}  // namespace hil::sim
