#pragma once
// The host-port firmware (a child process over pipes) or the Cortex-M7
// firmware under QEMU (its UART on stdio), planning over the framed link.
#include <memory>
#include <string>

#include "sim/planner_endpoint.hpp"

namespace hil::sim {

// target "host" or "qemu"; `firmware` "" uses this build's default. Returns
// nullptr (and fills `error`) if the target cannot be started.
std::unique_ptr<PlannerEndpoint> make_link_endpoint(const std::string& target, const std::string& firmware,
                                                    std::string* error = nullptr);

}  // namespace hil::sim
