#pragma once
// `hil_sim run`: its command-line options, and the run of a suite: load or
// generate the worlds, start the target, drive every scene through the
// closed loop (sim/closed_loop) with a progress bar, then write the trace,
// plots, report/1 and diagnostics and print the summary table.
// docs/simulation.md.
#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "apps/common_options.hpp"
#include "sim/commonroad_world.hpp"

namespace hil::apps {

struct RunCommand {
  std::vector<std::string> scene_files;  // scene/1 or CommonRoad XML files; empty: the generated suite
  sim::CommonRoadOptions commonroad;     // how CommonRoad files are imported
  std::string suite = "default";
  int count = 200;
  std::uint64_t seed = 1;
  TargetOptions target;                  // inproc | host | qemu, configuration, firmware, link key
  std::string prediction = "lane";       // lane | cv | truth (lane = cv on scenes without a lane map)
  std::string report;                    // report/1 path ("" = none)
  std::string plots;                     // directory for SVGs and index.html ("" = none)
  std::string trace;                     // JSON Lines file, one object per cycle ("" = none)
  std::string diagnostics;               // host / qemu: the firmware's Diagnostics after the run, JSON ("" = none)
  double duration = -1.0;                // [s] <= 0: each world's own
  std::string link_faults;               // host/qemu: "drop=P,dup=P,flip=P,reorder=P[,seed=N]" ("" = none)
  int link_deadline_ms = 0;              // host/qemu: per cycle, retransmissions included (<= 0: the target's default)
  bool fail_on_unsafe = false;           // exit 5 when a scene collides or leaves the road
};

// Adds `run`'s options, bound to `command`, to the subcommand `cmd`.
void add_run_options(CLI::App& cmd, RunCommand& command);

// Returns the process exit code: 0 when every scene ran (collisions are
// results), 2 on usage / setup errors (unreadable scene, unknown target,
// unwritable output), 3 when a scene crashed (the endpoint threw or a world
// has no usable reference line), 4 when the link failed: a link error on a
// link without injected faults, or (with --link-faults) a scene that never
// got a plan at all, 5 with --fail-on-unsafe when a scene collided or left
// the road. The report is written in every case but 2.
int run_command(const RunCommand& command);

}  // namespace hil::apps
