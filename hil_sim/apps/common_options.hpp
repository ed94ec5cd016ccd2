#pragma once
// The command-line options hil_sim and planner_cli share (CLI11), each with
// one help text and default: where the planner runs (--target, --firmware,
// --key), generated scenes (--count, --seed), obstacle predictions
// (--prediction) and CommonRoad import choices; and the planner endpoint a
// target names.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "sim/commonroad_world.hpp"
#include "sim/link_endpoint.hpp"
#include "sim/planner_endpoint.hpp"
#include "sim/scene_convert.hpp"
#include "sim/sim_config.hpp"

namespace hil::apps {

// Where the planner runs, with which configuration, and how the host
// reaches a firmware.
struct TargetOptions {
  std::string name = "inproc";    // inproc | host | qemu
  std::string config = "default";  // default | road (sim/sim_config.hpp)
  std::string firmware;           // host: executable, qemu: ELF ("" = this build's, of `config`)
  std::string key_file;           // the link key ("" = a fresh random key for the run)
};

// --target, one of `choices` (a subset of inproc, host, qemu); its default is
// the name `target` holds.
void add_target_option(CLI::App& cmd, TargetOptions& target, const std::vector<std::string>& choices);
// --firmware; `default_image` says what an empty value means.
void add_firmware_option(CLI::App& cmd, TargetOptions& target, const std::string& default_image = "this build's");
// --config default | road: the planner configuration (the firmware targets
// start that configuration's image unless --firmware names one).
void add_config_option(CLI::App& cmd, TargetOptions& target);
sim::SimConfig sim_config(const TargetOptions& target);
// --key: the link key file.
void add_key_option(CLI::App& cmd, TargetOptions& target);
// The firmware to start: --firmware, else the target's default image.
std::string firmware_image(const TargetOptions& target, const std::string& host_default,
                           const std::string& qemu_default);

// --count (positive) and --seed of the scene generator (same seed, same scenes).
void add_generator_options(CLI::App& cmd, int& count, std::uint64_t& seed);

// --prediction lane | cv | truth; its default is the value `prediction` holds.
void add_prediction_option(CLI::App& cmd, std::string& prediction);
sim::Prediction prediction_mode(const std::string& prediction);

// The CommonRoad import's choices, on `hil_sim import` and `hil_sim run` (for
// XML scenes). On import the run length is --duration (also
// --scenario-duration); on run, --duration already sets every scene's run length.
void add_commonroad_options(CLI::App& cmd, sim::CommonRoadOptions& options, bool on_import);

// The planner endpoint of `target` for configuration Cfg (which must be the
// one target.config names): the planner in this process (inproc) or a
// firmware over the link (host, qemu; `link` without its key file, which
// comes from `target`). nullptr, and `why` filled, when it cannot be used.
// Compiled for HIL_SIM_FOR_EACH_CONFIG.
template <class Cfg = itp::DefaultConfig>
std::unique_ptr<sim::BasicPlannerEndpoint<Cfg>> make_endpoint(const TargetOptions& target, sim::LinkOptions link,
                                                              std::string& why);

}  // namespace hil::apps
