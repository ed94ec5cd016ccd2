#include "apps/common_options.hpp"

#include <algorithm>
#include <utility>

#include <fmt/core.h>

#include "sim/inproc_endpoint.hpp"

namespace hil::apps {
namespace {

// What each target is, for --target's help.
std::string target_help(const std::vector<std::string>& choices) {
  const std::pair<const char*, const char*> known[] = {
      {"inproc", "the planner in this process"},
      {"host", "the host-port firmware as a child process"},
      {"qemu", "the Cortex-M7 firmware ELF under QEMU"},
  };
  std::string list;
  for (const auto& [name, what] : known) {
    if (std::find(choices.begin(), choices.end(), name) == choices.end()) continue;
    list += fmt::format("{}{} ({})", list.empty() ? "" : ", ", name, what);
  }
  return "Target: " + list;
}

}  // namespace

void add_target_option(CLI::App& cmd, TargetOptions& target, const std::vector<std::string>& choices) {
  cmd.add_option("--target", target.name, target_help(choices))->check(CLI::IsMember(choices))->capture_default_str();
}

void add_firmware_option(CLI::App& cmd, TargetOptions& target, const std::string& default_image) {
  cmd.add_option("--firmware", target.firmware,
                 "host/qemu: firmware executable (host) or ELF (qemu) (default: " + default_image + ")");
}

void add_config_option(CLI::App& cmd, TargetOptions& target) {
  cmd.add_option("--config", target.config,
                 "Planner configuration: default (10 static + 5 moving objects) or road (32 + 32, predictions every "
                 "0.2 s); host/qemu start that configuration's firmware unless --firmware is given")
      ->check(CLI::IsMember({"default", "road"}))
      ->capture_default_str();
}

sim::SimConfig sim_config(const TargetOptions& target) {
  return sim::parse_sim_config(target.config).value_or(sim::SimConfig::kDefault);
}

void add_key_option(CLI::App& cmd, TargetOptions& target) {
  cmd.add_option("--key", target.key_file,
                 "host/qemu: link key file (AES-128: 16 bytes or 32 hex digits; default: a fresh random key for the run)");
}

std::string firmware_image(const TargetOptions& target, const std::string& host_default,
                           const std::string& qemu_default) {
  if (!target.firmware.empty()) return target.firmware;
  return target.name == "qemu" ? qemu_default : host_default;
}

void add_generator_options(CLI::App& cmd, int& count, std::uint64_t& seed) {
  cmd.add_option("--count", count, "Number of generated scenes")->check(CLI::PositiveNumber)->capture_default_str();
  cmd.add_option("--seed", seed, "Generator seed (same seed, same scenes)")->capture_default_str();
}

void add_prediction_option(CLI::App& cmd, std::string& prediction) {
  cmd.add_option("--prediction", prediction,
                 "Obstacle predictions sent to the planner: lane (along the lane each obstacle is on, at its "
                 "current speed; constant velocity where no lane matches, and for scenes without a lane map: "
                 "generated scenes), cv (constant velocity) or truth (ground truth)")
      ->check(CLI::IsMember({"lane", "cv", "truth"}))
      ->capture_default_str();
}

sim::Prediction prediction_mode(const std::string& prediction) {
  if (prediction == "truth") return sim::Prediction::kGroundTruth;
  if (prediction == "lane") return sim::Prediction::kLane;
  return sim::Prediction::kConstantVelocity;
}

void add_commonroad_options(CLI::App& cmd, sim::CommonRoadOptions& o, bool on_import) {
  cmd.add_option("--planning-problem", o.planning_problem,
                 "CommonRoad: id of the planning problem that gives the ego (default: the first)");
  cmd.add_flag("--opposite-lanes", o.opposite_lanes,
               "CommonRoad: the drivable road includes the opposite-direction lanes beside the ego's");
  cmd.add_option("--speed-limit", o.speed_limit, "CommonRoad: speed limit [m/s] instead of the route's max-speed signs")
      ->check(CLI::PositiveNumber);
  cmd.add_option(on_import ? "--duration,--scenario-duration" : "--scenario-duration", o.duration,
                 "CommonRoad: run length [s] written into the scene (default: the goal's time interval end or the "
                 "last obstacle time step, at most 60 s)")
      ->check(CLI::PositiveNumber);
  cmd.add_flag("--drop-set-based", o.drop_set_based,
               "CommonRoad: leave obstacles with set-based predictions (occupancySet, phantomObstacle) out "
               "instead of refusing the file");
}

template <class Cfg>
std::unique_ptr<sim::BasicPlannerEndpoint<Cfg>> make_endpoint(const TargetOptions& target, sim::LinkOptions link,
                                                              std::string& why) {
  if (sim_config(target) != sim::sim_config_of<Cfg>()) {
    why = "--config " + target.config + " does not match the configuration planned with";
    return nullptr;
  }
  if (target.name == "inproc") return std::make_unique<sim::BasicInprocEndpoint<Cfg>>();
  if (target.name != "host" && target.name != "qemu") return nullptr;
  link.key_file = target.key_file;
  return sim::make_link_endpoint<Cfg>(target.name, target.firmware, &why, link);
}

#define HIL_APPS_INSTANTIATE_ENDPOINT(Cfg)                                                                 \
  template std::unique_ptr<sim::BasicPlannerEndpoint<Cfg>> make_endpoint<Cfg>(const TargetOptions&,     \
                                                                              sim::LinkOptions, std::string&);
HIL_SIM_FOR_EACH_CONFIG(HIL_APPS_INSTANTIATE_ENDPOINT)
#undef HIL_APPS_INSTANTIATE_ENDPOINT

}  // namespace hil::apps
