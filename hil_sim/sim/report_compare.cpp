#include "sim/report_compare.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include <fmt/core.h>

namespace hil::sim {

using nlohmann::json;

namespace {

bool flag(const json& scene, const char* key) {
  const auto it = scene.find(key);
  if (it == scene.end() || it->is_null()) return false;
  return it->is_boolean() ? it->get<bool>() : it->get<double>() > 0;
}

double number(const json& scene, const char* key) {
  const auto it = scene.find(key);
  return it == scene.end() || !it->is_number() ? 0.0 : it->get<double>();
}

json difference_json(const SceneDifference& d) {
  return json{{"name", d.name}, {"outcome_differs", d.outcome_differs}, {"progress_m", d.progress_m},
              {"min_clearance_m", d.min_clearance_m}, {"fallbacks", d.fallbacks}};
}

}  // namespace

json ReportComparison::to_json() const {
  json mm = json::array();
  for (const SceneDifference& d : mismatches) mm.push_back(difference_json(d));
  return json{{"format", "agreement/1"},       {"a", target_a},
              {"b", target_b},                 {"scenes", scenes},
              {"missing", missing},            {"outcome_mismatches", outcome_mismatches},
              {"identical_progress", identical_progress},
              {"median_abs_progress_m", median_progress_m},
              {"largest_progress", difference_json(largest_progress)},
              {"largest_clearance", difference_json(largest_clearance)},
              {"mismatches", mm},              {"agree", agree()}};
}

ReportComparison compare_reports(const json& a, const json& b) {
  ReportComparison out;
  if (!a.is_object() || !b.is_object() || !a.contains("per_scene") || !b.contains("per_scene")) {
    return out;
  }
  out.target_a = a.value("target", "a");
  out.target_b = b.value("target", "b");
  std::map<std::string, const json*> by_name;
  for (const json& s : b["per_scene"]) by_name[s.value("name", "")] = &s;
  std::vector<double> progress;
  std::size_t matched = 0;
  for (const json& sa : a["per_scene"]) {
    const auto it = by_name.find(sa.value("name", ""));
    if (it == by_name.end()) {
      ++out.missing;
      continue;
    }
    ++matched;
    const json& sb = *it->second;
    SceneDifference d;
    d.name = it->first;
    d.outcome_differs = flag(sa, "collisions") != flag(sb, "collisions") ||
                        flag(sa, "road_departures") != flag(sb, "road_departures") ||
                        flag(sa, "crashed") != flag(sb, "crashed");
    d.progress_m = std::fabs(number(sa, "progress_m") - number(sb, "progress_m"));
    const bool both_clear = sa.contains("min_clearance_m") && sb.contains("min_clearance_m") &&
                            sa["min_clearance_m"].is_number() && sb["min_clearance_m"].is_number();
    d.min_clearance_m = both_clear ? std::fabs(number(sa, "min_clearance_m") - number(sb, "min_clearance_m")) : 0.0;
    d.fallbacks = std::abs(static_cast<int>(number(sa, "fallbacks")) - static_cast<int>(number(sb, "fallbacks")));
    ++out.scenes;
    progress.push_back(d.progress_m);
    out.identical_progress += d.progress_m < 1e-3 ? 1 : 0;
    if (d.outcome_differs) {
      ++out.outcome_mismatches;
      out.mismatches.push_back(d);
    }
    if (out.scenes == 1 || d.progress_m > out.largest_progress.progress_m) out.largest_progress = d;
    if (out.scenes == 1 || d.min_clearance_m > out.largest_clearance.min_clearance_m) out.largest_clearance = d;
  }
  out.missing += static_cast<int>(b["per_scene"].size() - matched);
  if (!progress.empty()) {
    std::sort(progress.begin(), progress.end());
    const std::size_t n = progress.size();
    out.median_progress_m = n % 2 == 1 ? progress[n / 2] : 0.5 * (progress[n / 2 - 1] + progress[n / 2]);
  }
  return out;
}

int compare_command(const std::string& file_a, const std::string& file_b, const std::string& json_out) {
  json docs[2];
  const std::string files[2] = {file_a, file_b};
  for (int i = 0; i < 2; ++i) {
    std::ifstream in(files[i]);
    docs[i] = json::parse(in, nullptr, false);
    if (!in || docs[i].is_discarded() || docs[i].value("format", "") != "report/1") {
      fmt::print(stderr, "hil_sim compare: '{}' is not a readable report/1 file\n", files[i]);
      return 2;
    }
  }
  const ReportComparison c = compare_reports(docs[0], docs[1]);
  fmt::print("hil_sim compare: {} ({}) vs {} ({})\n", file_a, c.target_a, file_b, c.target_b);
  fmt::print("  scenes compared            {}{}\n", c.scenes, c.missing > 0 ? fmt::format(" ({} missing)", c.missing) : "");
  fmt::print("  safety outcome mismatches  {}\n", c.outcome_mismatches);
  for (const SceneDifference& d : c.mismatches) fmt::print("    {}\n", d.name);
  fmt::print("  identical progress         {} of {}\n", c.identical_progress, c.scenes);
  fmt::print("  |Δprogress| median / max   {:.3g} m / {:.3g} m ({})\n", c.median_progress_m,
             c.largest_progress.progress_m, c.largest_progress.name);
  fmt::print("  |Δmin clearance| max       {:.3g} m ({})\n", c.largest_clearance.min_clearance_m,
             c.largest_clearance.name);
  fmt::print("  verdict                    {}\n", c.agree() ? "agree" : "DISAGREE");
  if (!json_out.empty()) {
    std::ofstream out(json_out);
    out << c.to_json().dump(2) << '\n';
    if (!out) {
      fmt::print(stderr, "hil_sim compare: cannot write '{}'\n", json_out);
      return 2;
    }
  }
  return c.agree() ? 0 : 1;
}

}  // namespace hil::sim
