#pragma once
// The host-port firmware (a child process over pipes) or the Cortex-M7
// firmware under QEMU (its UART on stdio), planning over the framed,
// authenticated link (docs/protocol.md).
#include <chrono>
#include <memory>
#include <string>

#include "link/fault_injection.hpp"
#include "sim/planner_endpoint.hpp"

namespace hil::sim {

struct LinkOptions {
  std::string key_file;  // the firmware's link key ("": a fresh random key for this run)
  // Per planning cycle: the reply must be complete by then, retransmissions
  // included (<= 0: 1 s on host, 20 s on qemu, whose emulation is far slower
  // than the target it stands for).
  std::chrono::milliseconds deadline{0};
  hil::LinkFaults faults{};  // bytes dropped, duplicated, flipped, reordered on the way (both directions)
};

// This build's firmware for `target` ("host": the host-port executable,
// "qemu": the Cortex-M7 ELF) planning with `config` (the road image for
// SimConfig::kRoad).
std::string default_firmware(const std::string& target, SimConfig config);

// target "host" or "qemu"; `firmware` "" uses this build's firmware of
// configuration Cfg (default_firmware). The firmware must plan with Cfg: the
// Scene and Plan messages are sized by it. Returns nullptr (and fills
// `error`) if the target cannot be started. Compiled for HIL_SIM_FOR_EACH_CONFIG.
template <class Cfg = itp::DefaultConfig>
std::unique_ptr<BasicPlannerEndpoint<Cfg>> make_link_endpoint(const std::string& target, const std::string& firmware,
                                                              std::string* error = nullptr,
                                                              const LinkOptions& options = {});

}  // namespace hil::sim
