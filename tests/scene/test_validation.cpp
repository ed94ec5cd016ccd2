// Every ValidationReason the validator can produce, each from a dedicated
// mutation of a valid scene. The capacity reasons (too_many_*) are produced
// by the JSON reader, whose tests cover them (test_scene_json.cpp).
#include <doctest/doctest.h>

#include <cstring>
#include <functional>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "heap_guard.hpp"
#include "itp/scene/validation.hpp"
#include "scene_builders.hpp"

using itp::Scalar;
using itp::scene::Scene;
using itp::scene::ValidationReason;
using R = ValidationReason;

namespace {

constexpr Scalar kNaN = std::numeric_limits<Scalar>::quiet_NaN();
constexpr Scalar kInf = std::numeric_limits<Scalar>::infinity();

struct Case {
  const char* name;
  R expected;
  std::function<void(Scene&)> mutate;
  Scalar now = Scalar(0);  // [s] the scene time it is validated at
};

const std::vector<Case>& cases() {
  static const std::vector<Case> all = {
      {"NaN in the reference line", R::kNonFiniteValue, [](Scene& s) { s.reference_line[3].y = kNaN; }},
      {"Inf ego speed", R::kNonFiniteValue, [](Scene& s) { s.ego.state.v = kInf; }},
      {"NaN obstacle width", R::kNonFiniteValue, [](Scene& s) { s.static_obstacles[0].width = kNaN; }},
      {"NaN prediction time", R::kNonFiniteValue,
       [](Scene& s) { s.dynamic_obstacles[0].trajectory[1].t = kNaN; }},
      {"NaN speed limit", R::kNonFiniteValue, [](Scene& s) { s.road.speed_limit = kNaN; }},
      {"NaN ego limit", R::kNonFiniteValue, [](Scene& s) { s.ego.limits.kappa_max = kNaN; }},
      {"absurd coordinate", R::kCoordinateOutOfRange, [](Scene& s) { s.static_obstacles[0].x = Scalar(2e5); }},
      {"one reference point", R::kTooFewReferencePoints, [](Scene& s) { (void)s.reference_line.resize(1); }},
      {"repeated reference point", R::kRepeatedReferencePoints,
       [](Scene& s) { s.reference_line[5] = s.reference_line[4]; }},
      {"reference line reverses", R::kReferenceLineSharpTurn,
       [](Scene& s) { s.reference_line[10] = {Scalar(40), Scalar(0.5)}; }},
      {"reference line 0.6 m long", R::kReferenceLineTooShort,
       [](Scene& s) {
         (void)s.reference_line.resize(2);
         s.reference_line[1] = {Scalar(0.6), Scalar(0)};
       }},
      {"lane width 1 m", R::kLaneWidthOutOfRange, [](Scene& s) { s.road.lane_width = Scalar(1); }},
      {"lane width 9 m", R::kLaneWidthOutOfRange, [](Scene& s) { s.road.lane_width = Scalar(9); }},
      {"boundary 80 m away", R::kBoundaryOutOfRange, [](Scene& s) { s.road.left.offset = Scalar(80); }},
      {"boundary table s not ascending", R::kBoundaryTableNotAscending,
       [](Scene& s) {
         (void)s.road.left.table.push_back({Scalar(0), Scalar(5)});
         (void)s.road.left.table.push_back({Scalar(50), Scalar(5)});
         (void)s.road.left.table.push_back({Scalar(50), Scalar(4)});
       }},
      {"left boundary below right (constant)", R::kBoundariesCrossed,
       [](Scene& s) { s.road.left.offset = Scalar(-2); }},
      {"boundary tables cross at s = 60", R::kBoundariesCrossed,
       [](Scene& s) {
         (void)s.road.left.table.push_back({Scalar(0), Scalar(5)});
         (void)s.road.left.table.push_back({Scalar(60), Scalar(-2)});
       }},
      {"target lane 60 m away", R::kTargetLaneOffsetOutOfRange,
       [](Scene& s) { s.road.target_lane_offset = Scalar(60); }},
      {"speed limit 0", R::kSpeedLimitOutOfRange, [](Scene& s) { s.road.speed_limit = Scalar(0); }},
      {"speed limit 80 m/s", R::kSpeedLimitOutOfRange, [](Scene& s) { s.road.speed_limit = Scalar(80); }},
      {"ego reversing", R::kEgoSpeedOutOfRange, [](Scene& s) { s.ego.state.v = Scalar(-1); }},
      {"ego 100 m/s", R::kEgoSpeedOutOfRange, [](Scene& s) { s.ego.state.v = Scalar(100); }},
      {"ego acceleration 30", R::kEgoAccelerationOutOfRange, [](Scene& s) { s.ego.state.a = Scalar(30); }},
      {"ego curvature 2", R::kEgoCurvatureOutOfRange, [](Scene& s) { s.ego.state.kappa = Scalar(2); }},
      {"ego negative width", R::kEgoGeometryOutOfRange, [](Scene& s) { s.ego.geometry.width = Scalar(-1.9); }},
      {"ego wheelbase longer than the car", R::kEgoGeometryOutOfRange,
       [](Scene& s) { s.ego.geometry.wheelbase = Scalar(5); }},
      {"ego a_min positive", R::kEgoLimitsOutOfRange, [](Scene& s) { s.ego.limits.a_min = Scalar(1); }},
      {"ego lateral limit 0", R::kEgoLimitsOutOfRange, [](Scene& s) { s.ego.limits.lat_acc_max = Scalar(0); }},
      {"ego 12 m beside the line", R::kEgoFarFromReferenceLine, [](Scene& s) { s.ego.state.y = Scalar(12); }},
      {"ego 20 m behind the start", R::kEgoFarFromReferenceLine, [](Scene& s) { s.ego.state.x = Scalar(-20); }},
      {"static obstacle zero length", R::kObstacleSizeOutOfRange,
       [](Scene& s) { s.static_obstacles[0].length = Scalar(0); }},
      {"dynamic obstacle 40 m wide", R::kObstacleSizeOutOfRange,
       [](Scene& s) { s.dynamic_obstacles[0].width = Scalar(40); }},
      {"static and dynamic share an id", R::kDuplicateObstacleId,
       [](Scene& s) { s.dynamic_obstacles[0].id = s.static_obstacles[0].id; }},
      {"dynamic obstacle without samples", R::kEmptyTrajectory,
       [](Scene& s) { s.dynamic_obstacles[0].trajectory.clear(); }},
      {"equal prediction times", R::kPredictionTimesNotIncreasing,
       [](Scene& s) { s.dynamic_obstacles[0].trajectory[1].t = Scalar(0); }},
      {"decreasing prediction times", R::kPredictionTimesNotIncreasing,
       [](Scene& s) {
         s.dynamic_obstacles[0].trajectory[0].t = Scalar(0.5);
         s.dynamic_obstacles[0].trajectory[1].t = Scalar(0.2);
       }},
      {"prediction two hours before now", R::kPredictionTimeOutOfRange,
       [](Scene& s) { s.dynamic_obstacles[0].trajectory[0].t = Scalar(-7200); }},
      {"prediction two hours after now", R::kPredictionTimeOutOfRange,
       [](Scene& s) { s.dynamic_obstacles[0].trajectory[1].t = Scalar(7200); }},
      {"predictions of t = 0 at now = 2 h", R::kPredictionTimeOutOfRange, [](Scene&) {}, Scalar(7200)},
      {"obstacle at 90 m/s", R::kObstacleSpeedOutOfRange,
       [](Scene& s) { s.dynamic_obstacles[0].trajectory[1].v = Scalar(90); }},
      // Issue 13, defect 1: the scene time itself.
      {"scene time NaN", R::kSceneTimeOutOfRange, [](Scene&) {}, kNaN},
      {"scene time +Inf", R::kSceneTimeOutOfRange, [](Scene&) {}, kInf},
      {"scene time -Inf", R::kSceneTimeOutOfRange, [](Scene&) {}, -kInf},
      {"scene time 1e300", R::kSceneTimeOutOfRange, [](Scene&) {}, std::numeric_limits<Scalar>::max()},
      {"scene time -1 s", R::kSceneTimeOutOfRange, [](Scene&) {}, Scalar(-1)},
      // Issue 13, defect 9: headings bounded, sizes and limits bounded below.
      {"ego heading 1e30", R::kHeadingOutOfRange, [](Scene& s) { s.ego.state.heading = Scalar(1e30); }},
      {"static obstacle heading 30 rad", R::kHeadingOutOfRange,
       [](Scene& s) { s.static_obstacles[0].heading = Scalar(30); }},
      {"prediction heading -1e30", R::kHeadingOutOfRange,
       [](Scene& s) { s.dynamic_obstacles[0].trajectory[1].heading = Scalar(-1e30); }},
      {"static obstacle 1e-30 m long", R::kObstacleSizeOutOfRange,
       [](Scene& s) { s.static_obstacles[0].length = Scalar(1e-30); }},
      {"dynamic obstacle 1e-30 m wide", R::kObstacleSizeOutOfRange,
       [](Scene& s) { s.dynamic_obstacles[0].width = Scalar(1e-30); }},
      {"ego 1e-30 m wide", R::kEgoGeometryOutOfRange, [](Scene& s) { s.ego.geometry.width = Scalar(1e-30); }},
      {"ego wheelbase 1e-30 m", R::kEgoGeometryOutOfRange,
       [](Scene& s) { s.ego.geometry.wheelbase = Scalar(1e-30); }},
      {"ego a_max 1e-30", R::kEgoLimitsOutOfRange, [](Scene& s) { s.ego.limits.a_max = Scalar(1e-30); }},
      {"ego a_min -1e-30", R::kEgoLimitsOutOfRange, [](Scene& s) { s.ego.limits.a_min = Scalar(-1e-30); }},
      {"ego lateral limit 1e-30", R::kEgoLimitsOutOfRange,
       [](Scene& s) { s.ego.limits.lat_acc_max = Scalar(1e-30); }},
      {"ego curvature limit 1e-30", R::kEgoLimitsOutOfRange,
       [](Scene& s) { s.ego.limits.kappa_max = Scalar(1e-30); }},
      {"speed limit 1e-30", R::kSpeedLimitOutOfRange, [](Scene& s) { s.road.speed_limit = Scalar(1e-30); }},
  };
  return all;
}

}  // namespace

TEST_CASE("The baseline scene is valid, and validating it does not allocate") {
  static Scene s;
  s = scene_test::baseline_scene();
  test_support::HeapGuard guard;
  const auto r = itp::scene::validate(s, Scalar(0));
  CHECK(r.ok());
  CHECK(r.status() == itp::PlanStatus::kOk);
  CHECK(itp::scene::validate(s).ok());
}

// Issue 13, defect 3: prediction times are judged relative to the scene
// time, so a scene with moving obstacles keeps validating after an hour,
// a day, a month. (Before, t above 3600 s was rejected outright.)
TEST_CASE("Predictions relative to the scene time: nothing expires after an hour or a day") {
  static Scene s;
  for (const double now : {3592.0, 4000.0, 86400.0, 3.0e6}) {
    s = scene_test::baseline_scene();
    for (auto& p : s.dynamic_obstacles[0].trajectory) p.t += Scalar(now);
    CHECK_MESSAGE(itp::scene::validate(s).ok(), "now = ", now, ": ", itp::scene::to_string(itp::scene::validate(s).reason));
    CHECK(itp::scene::validate(s, Scalar(now)).ok());
    // The same predictions an hour and a half stale are out of range.
    CHECK(itp::scene::validate(s, Scalar(now + 5400)).reason == R::kPredictionTimeOutOfRange);
  }
}

TEST_CASE("Each invalid input is rejected with its own reason") {
  for (const Case& c : cases()) {
    SUBCASE(c.name) {
      Scene s = scene_test::baseline_scene();
      c.mutate(s);
      const auto r = itp::scene::validate(s, c.now);
      CHECK_MESSAGE(r.reason == c.expected, c.name, ": got ", itp::scene::to_string(r.reason));
      CHECK(r.status() == itp::PlanStatus::kInvalidInput);
    }
  }
}

TEST_CASE("Every reason is covered by a case here or by the JSON reader tests") {
  std::set<R> covered;
  for (const Case& c : cases()) covered.insert(c.expected);
  // Produced by the reader on overflow (test_scene_json.cpp):
  for (R r : {R::kTooManyReferencePoints, R::kTooManyBoundaryPoints, R::kTooManyStaticObstacles,
              R::kTooManyDynamicObstacles, R::kTooManyPredictionSamples}) {
    covered.insert(r);
  }
  std::set<std::string> names;
  for (int v = 1; v <= static_cast<int>(R::kHeadingOutOfRange); ++v) {
    const R r = static_cast<R>(v);
    CHECK_MESSAGE(covered.count(r) == 1, "no test case for ", itp::scene::to_string(r));
    const std::string name = itp::scene::to_string(r);
    CHECK(name != "unknown");
    CHECK(names.insert(name).second);  // names are unique
  }
}

TEST_CASE("Boundary tables interpolate linearly and hold their end values") {
  itp::scene::Boundary b;
  b.offset = Scalar(9);  // ignored once a table exists
  CHECK(b.at(Scalar(3)) == Scalar(9));
  (void)b.table.push_back({Scalar(10), Scalar(4)});
  (void)b.table.push_back({Scalar(30), Scalar(2)});
  (void)b.table.push_back({Scalar(40), Scalar(3)});
  CHECK(b.at(Scalar(0)) == Scalar(4));
  CHECK(static_cast<double>(b.at(Scalar(20))) == doctest::Approx(3.0));
  CHECK(static_cast<double>(b.at(Scalar(35))) == doctest::Approx(2.5));
  CHECK(b.at(Scalar(100)) == Scalar(3));
}
