#pragma once
// Agreement between two closed-loop runs of the same scenes (report/1 files),
// e.g. the qemu target against the host one: the safety outcome of every
// scene (collision, road departure, crash) must match; the continuous figures
// (progress, clearance, fallbacks) may drift where a floating-point difference
// between the targets' maths libraries tips a discrete choice in the loop.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace hil::sim {

struct SceneDifference {
  std::string name;
  bool outcome_differs = false;  // collision, departure or crash flag differs
  double progress_m = 0.0;       // |a - b|
  double min_clearance_m = 0.0;  // |a - b| (0 when either is null)
  int fallbacks = 0;             // |a - b|
};

struct ReportComparison {
  std::string target_a, target_b;
  int scenes = 0;                  // scenes present in both
  int missing = 0;                 // scenes in only one of them
  int outcome_mismatches = 0;      // scenes whose safety outcome differs
  int identical_progress = 0;      // scenes with |Δprogress| < 1 mm
  SceneDifference largest_progress;   // the scene with the largest |Δprogress|
  SceneDifference largest_clearance;  // ... the largest |Δmin clearance|
  double median_progress_m = 0.0;     // median |Δprogress| over the scenes
  std::vector<SceneDifference> mismatches;  // the outcome mismatches
  bool agree() const { return missing == 0 && outcome_mismatches == 0 && scenes > 0; }
  nlohmann::json to_json() const;
};

// Compares the per_scene entries of two report/1 documents by scene name.
// An unreadable document gives scenes = 0 (and agree() = false).
ReportComparison compare_reports(const nlohmann::json& a, const nlohmann::json& b);

// `hil_sim compare A.json B.json [--json OUT]`: prints the comparison;
// returns 0 when the runs agree, 1 when they do not, 2 on unreadable input.
int compare_command(const std::string& file_a, const std::string& file_b, const std::string& json_out);

}  // namespace hil::sim
