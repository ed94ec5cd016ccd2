#pragma once
// The printed summary of a closed-loop suite (`hil_sim run`, index.html).
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace hil::sim {

// The fmt summary table of a suite (report/1 as written by SuiteAggregator).
std::string summary_table(const nlohmann::json& report);

}  // namespace hil::sim
