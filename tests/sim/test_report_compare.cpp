#include <doctest/doctest.h>

#include "sim/report_compare.hpp"

using hil::sim::compare_reports;
using nlohmann::json;

namespace {

json scene(const std::string& name, int collisions, int departures, double progress, json clearance) {
  return json{{"name", name},        {"collisions", collisions}, {"road_departures", departures},
              {"crashed", false},    {"progress_m", progress},   {"min_clearance_m", clearance},
              {"fallbacks", 0}};
}

json report(const std::string& target, std::vector<json> scenes) {
  return json{{"format", "report/1"}, {"target", target}, {"per_scene", scenes}};
}

}  // namespace

TEST_CASE("compare: identical runs agree with zero differences") {
  const json a = report("host", {scene("s0", 0, 0, 90.0, 1.5), scene("s1", 0, 0, 80.0, nullptr)});
  const auto c = compare_reports(a, a);
  CHECK(c.agree());
  CHECK(c.scenes == 2);
  CHECK(c.identical_progress == 2);
  CHECK(c.largest_progress.progress_m == 0.0);
  CHECK(c.median_progress_m == 0.0);
}

TEST_CASE("compare: drift in progress is reported but a matching safety outcome agrees") {
  const json a = report("host", {scene("s0", 0, 0, 90.0, 1.5), scene("s1", 0, 0, 80.0, 2.0), scene("s2", 0, 0, 70.0, 1.0)});
  const json b = report("qemu", {scene("s2", 0, 0, 70.0, 1.0), scene("s0", 0, 0, 90.5, 1.25), scene("s1", 0, 0, 77.0, 2.0)});
  const auto c = compare_reports(a, b);
  CHECK(c.agree());
  CHECK(c.target_a == "host");
  CHECK(c.target_b == "qemu");
  CHECK(c.identical_progress == 1);
  CHECK(c.largest_progress.name == "s1");
  CHECK(c.largest_progress.progress_m == doctest::Approx(3.0));
  CHECK(c.median_progress_m == doctest::Approx(0.5));
  CHECK(c.largest_clearance.name == "s0");
  CHECK(c.largest_clearance.min_clearance_m == doctest::Approx(0.25));
}

TEST_CASE("compare: a collision in one run only, or a missing scene, is a disagreement") {
  const json a = report("host", {scene("s0", 0, 0, 90.0, 1.5), scene("s1", 0, 0, 80.0, 2.0)});
  const json b = report("qemu", {scene("s0", 1, 0, 90.0, 0.0), scene("s1", 0, 0, 80.0, 2.0)});
  const auto c = compare_reports(a, b);
  CHECK_FALSE(c.agree());
  CHECK(c.outcome_mismatches == 1);
  REQUIRE(c.mismatches.size() == 1);
  CHECK(c.mismatches[0].name == "s0");

  const json shorter = report("qemu", {scene("s0", 0, 0, 90.0, 1.5)});
  const auto m = compare_reports(a, shorter);
  CHECK_FALSE(m.agree());
  CHECK(m.missing == 1);
  CHECK_FALSE(compare_reports(json::object(), a).agree());
}
