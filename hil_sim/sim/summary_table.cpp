#include "sim/summary_table.hpp"

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

#include <fmt/core.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace hil::sim {

using nlohmann::json;

namespace {

std::string num(const json& j, const char* spec = "{:.2f}") {
  if (j.is_null()) return "-";
  if (j.is_number_integer()) return fmt::format("{}", j.get<long long>());
  return fmt::format(fmt::runtime(spec), j.get<double>());
}

}  // namespace

std::string summary_table(const json& rep) {
  std::vector<std::pair<std::string, std::string>> rows;
  auto row = [&](std::string k, std::string v) { rows.emplace_back(std::move(k), std::move(v)); };
  row("target", rep.value("target", std::string("?")));
  row("scenes", num(rep["scenes"]));
  row("cycles", num(rep["cycles"]));
  row("collisions (scenes)", fmt::format("{} ({} steps)", num(rep["collisions"]), num(rep["collision_steps"])));
  if (rep.contains("collisions_ran_into")) {
    row("  the ego ran into / was hit", fmt::format("{} / {}", num(rep["collisions_ran_into"]), num(rep["collisions_hit"])));
  }
  row("road departures (scenes)", fmt::format("{} ({} steps)", num(rep["road_departures"]), num(rep["road_departure_steps"])));
  std::string reasons;
  for (const auto& [k, v] : rep["fallback_reasons"].items()) {
    reasons += fmt::format("{}{} {}", reasons.empty() ? "" : ", ", k, v.get<int>());
  }
  row("fallbacks", fmt::format("{}{}", num(rep["fallbacks"]), reasons.empty() ? "" : " (" + reasons + ")"));
  std::map<std::string, int> invalid;
  for (const auto& sc : rep["per_scene"]) {
    if (sc.contains("invalid_input_reasons")) {
      for (const auto& [k, v] : sc["invalid_input_reasons"].items()) invalid[k] += v.get<int>();
    }
  }
  std::string inv;
  for (const auto& [k, v] : invalid) inv += fmt::format("{}{} {}", inv.empty() ? "" : ", ", k, v);
  row("invalid inputs", fmt::format("{}{}", num(rep["invalid_inputs"]), inv.empty() ? "" : " (" + inv + ")"));
  row("link errors", num(rep["link_errors"]));
  if (rep.contains("link")) {
    const json& l = rep["link"];
    row("cycles without a fresh plan", fmt::format("{} ({:.2f} %), corrupt scenes accepted {}", num(rep["link_errors"]),
                                                   100.0 * rep.value("share_without_fresh_plan", 0.0),
                                                   num(rep["corrupt_scenes_accepted"])));
    row("link: queries / statuses / resent", fmt::format("{} / {} / {}", num(l["queries"]), num(l["statuses"]),
                                                         num(l["segments_resent"])));
    if (l.contains("faults_to_firmware")) {
      row("link: byte faults to fw / to host", fmt::format("{} / {}", num(l["faults_to_firmware"]),
                                                           num(l["faults_to_host"])));
    }
  }
  row("crashes", num(rep["crashes"]));
  if (rep.contains("obstacles_left_out")) {
    const json& lo = rep["obstacles_left_out"];
    row("obstacles left out (capacity)", fmt::format("{} cycles, {} in all, at most {} in a cycle", num(lo["cycles"]),
                                                     num(lo["total"]), num(lo["max_per_cycle"])));
  }
  row("min clearance [m]", num(rep["min_clearance_m"], "{:.3f}"));
  row("max |a_lon| [m/s²]", num(rep["max_abs_lon_acc"]));
  row("max |a_lat| [m/s²]", num(rep["max_abs_lat_acc"]));
  row("max |jerk| [m/s³]", num(rep["max_abs_jerk"], "{:.1f}"));
  row("max plan deviation [m]", num(rep["max_plan_deviation_m"], "{:.3f}"));
  row("path deviation [m] scene median / max",
      fmt::format("{} / {}", num(rep["median_scene_path_deviation_m"], "{:.3f}"), num(rep["max_path_deviation_m"], "{:.3f}")));
  row("iterations mean / max", fmt::format("{} / {}", num(rep["iterations"]["mean"]), num(rep["iterations"]["max"])));
  const json& ct = rep["cycle_time_us"];
  if (!ct["median"].is_null()) {
    row("cycle time [µs] median / p99 / max",
        fmt::format("{} / {} / {}", num(ct["median"], "{:.0f}"), num(ct["p99"], "{:.0f}"), num(ct["max"], "{:.0f}")));
  }
  const json& in = rep["instructions_per_cycle"];
  if (!in["median"].is_null()) {
    row("instructions / cycle median / max", fmt::format("{} / {}", num(in["median"], "{:.3g}"), num(in["max"], "{:.3g}")));
  }
  const double progress = rep.value("progress_m_total", 0.0);
  const int scenes = rep.value("scenes", 0);
  row("progress [m] total / mean per scene",
      fmt::format("{:.0f} / {:.1f}", progress, scenes > 0 ? progress / scenes : 0.0));

  std::size_t w = 0;
  for (const auto& [k, v] : rows) w = std::max(w, k.size());
  std::string out = fmt::format("{:-<{}}\n", "", w + 40);
  for (const auto& [k, v] : rows) out += fmt::format("{:<{}}  {}\n", k, w, v);
  out += fmt::format("{:-<{}}\n", "", w + 40);
  return out;
}

}  // namespace hil::sim
