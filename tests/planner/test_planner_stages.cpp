// Each planner stage on its own (planner/*.hpp), against hand-derived
// expectations on straight roads, where the Frenet frame is the world frame
// shifted: s = x, l = y.
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "itp/geometry/reference_line.hpp"
#include "itp/geometry/smoothing_spline.hpp"
#include "itp/planner/collision_check.hpp"
#include "itp/planner/curvature_bounds.hpp"
#include "itp/planner/decision_choice.hpp"
#include "itp/decision/decision_tree.hpp"
#include "itp/planner/safe_stop.hpp"
#include "itp/planner/sl_scene.hpp"
#include "scene_builder.hpp"

using namespace itp::planner;
using namespace planner_test;
using Cfg = itp::DefaultConfig;
using Line = itp::geometry::BasicReferenceLine<Cfg>;

namespace {

// The scene's reference line fitted as the planner does.
struct Fitted {
  std::unique_ptr<itp::geometry::BasicSmoothingSplineWorkspace<Cfg>> ws =
      std::make_unique<itp::geometry::BasicSmoothingSplineWorkspace<Cfg>>();
  std::unique_ptr<Line> line = std::make_unique<Line>();
  explicit Fitted(const Scene& s) {
    REQUIRE(line->build(s.reference_line.span(), *ws) == itp::geometry::ReferenceLineStatus::kOk);
  }
};

const PlannerSettings kSettings{};

}  // namespace

TEST_CASE("SL scene: a static box is the obstacle's extent, inflated by the margin and in s by the ego") {
  Scene s = road_scene(1, 0);
  add_static(s, 3, 50, 0.5, 0, 4.0, 2.0);  // x in [48, 52], y in [-0.5, 1.5]
  Fitted f(s);
  auto sl = std::make_unique<BasicSlScene<Cfg>>();
  sl->build(s, *f.line, 0, 0, 100, kSettings);
  REQUIRE(sl->boxes().size() == 1);
  const auto& b = sl->boxes()[0];
  const double m = kSettings.static_margin;
  const double rear = 0.5 * (4.8 - 2.8);  // ego: 4.8 m long, wheelbase 2.8 m
  const double front = 4.8 - rear;
  CHECK(b.obstacle_id == 3);
  CHECK_FALSE(b.dynamic);
  CHECK(b.s_min == doctest::Approx(48 - m - front).epsilon(1e-6));
  CHECK(b.s_max == doctest::Approx(52 + m + rear).epsilon(1e-6));
  CHECK(b.l_min == doctest::Approx(-0.5 - m).epsilon(1e-6));
  CHECK(b.l_max == doctest::Approx(1.5 + m).epsilon(1e-6));
  CHECK(sl->static_boxes().size() == 1);
  // The road edges move inwards by the road margin.
  CHECK(sl->road().left.at(20) == doctest::Approx(1.75 + 3.5 - kSettings.road_margin));
  CHECK(sl->road().right.at(20) == doctest::Approx(-1.75 + kSettings.road_margin));
}

TEST_CASE("SL scene: movers are classified where first seen (oncoming, crossing, from behind)") {
  Scene s = road_scene(1, 0);
  add_mover(s, 11, 80, 3.5, M_PI, 10);             // oncoming in the left lane
  add_mover(s, 12, 60, -3, M_PI / 2, 1.2, 0.8, 0.8);  // a pedestrian crossing from the right
  add_mover(s, 13, -15, 3.5, 0, 15);               // faster car behind in the left lane
  add_mover(s, 14, 40, 0, 0, 5);                    // a slow leader in the ego's lane
  Fitted f(s);
  auto sl = std::make_unique<BasicSlScene<Cfg>>();
  sl->build(s, *f.line, 0, 0, 100, kSettings);
  REQUIRE(sl->tracks().size() == 4);
  const auto& t = sl->tracks();
  CHECK(t[0].sweep_occupied);
  CHECK_FALSE(t[0].crossing);
  CHECK(t[1].crossing);
  CHECK_FALSE(t[1].sweep_occupied);
  CHECK(t[2].sweep_occupied);
  CHECK_FALSE(t[3].sweep_occupied);
  CHECK_FALSE(t[3].crossing);
  // The crossing pedestrian's boxes are widened sideways by 1 m each side
  // (its 0.8 m plus the dynamic margin, plus 1 m).
  const auto& ped = t[1].box[0];
  CHECK(ped.l_max - ped.l_min == doctest::Approx(0.8 + 2 * kSettings.dynamic_margin + 2.0).epsilon(1e-6));
  // The leader's motion at 1 s: 5 m further on.
  CHECK(sl->motions()[3][10].x == doctest::Approx(45).epsilon(1e-9));
}

TEST_CASE("SL scene: a car behind the reference line's start on a bend keeps its lane") {
  // A left bend of R = 250 m starting at the reference line's first point; a
  // car 15 m behind that point in the left lane (on the bend's continuation)
  // at 15 m/s, predicted at constant velocity. Behind the line's start the
  // frame runs straight, so the car's heading differs from the road's where
  // its straight-line prediction reaches the line by the bend (3.5 deg), not
  // by a lane change: it must not be predicted into the ego's lane.
  const double radius = 250;
  Scene s = road_scene(1, 0, radius, 200);
  s.ego.state.x = radius * std::sin(40.0 / radius);
  s.ego.state.y = radius * (1 - std::cos(40.0 / radius));
  s.ego.state.heading = 40.0 / radius;
  const double r_lane = radius - 3.5;
  const double phi = -15.0 / r_lane;
  add_mover(s, 21, r_lane * std::sin(phi), radius - r_lane * std::cos(phi), phi, 15);
  Fitted f(s);
  auto sl = std::make_unique<BasicSlScene<Cfg>>();
  sl->build(s, *f.line, 0, 40, 150, kSettings);
  REQUIRE(sl->motions().size() == 1);
  for (std::size_t k = 10; k < static_cast<std::size_t>(Cfg::kStSamples); k += 10) {
    const auto& m = sl->motions()[0][k];
    REQUIRE(m.present);
    const auto fr = f.line->to_frenet(itp::geometry::Point2{m.x, m.y});
    CHECK(fr.l > 2.5);  // its lane [1.75, 5.25]; the ego's lane ends at 1.75
  }
}

TEST_CASE("SL scene: a car whose body fits the road keeps its box where it is") {
  // Narrow two-way road (lanes 2.76 m, edges -1.38 / 4.14); an oncoming car
  // (1.85 m) in the left lane's centre. Its box with the 0.5 m margin reaches
  // 0.05 m beyond the edge, its body does not: it is not moved. Kept inside
  // the edges less the road margin, it was pushed 0.2 m towards the ego.
  Scene s = road_scene(1, 0);
  s.road.lane_width = 2.76;
  s.road.right.offset = -1.38;
  s.road.left.offset = 4.14;
  add_mover(s, 102, 80, 2.76, M_PI, 10, 4.41, 1.85);
  // ... and a car that does stick out over the left edge by 0.3 m: its body
  // is moved back inside the real edge.
  add_mover(s, 103, 120, 4.14 - 0.925 + 0.3, M_PI, 10, 4.41, 1.85);
  Fitted f(s);
  auto sl = std::make_unique<BasicSlScene<Cfg>>();
  sl->build(s, *f.line, 0, 0, 100, kSettings);
  REQUIRE(sl->tracks().size() == 2);
  for (std::size_t k = 0; k < static_cast<std::size_t>(Cfg::kStSamples); k += 10) {
    const auto& b = sl->tracks()[0].box[k];
    CHECK(b.l_min == doctest::Approx(2.76 - 0.925 - kSettings.dynamic_margin).epsilon(1e-3));
    const auto& c = sl->tracks()[1].box[k];
    CHECK(c.l_max - kSettings.dynamic_margin == doctest::Approx(4.14).epsilon(1e-3));
  }
}

TEST_CASE("SL scene: a leader is placed where the guessed ego motion meets it, the crossing mover never") {
  Scene s = road_scene(1, 0);
  add_mover(s, 12, 60, -3, M_PI / 2, 1.2, 0.8, 0.8);  // crossing: the ST graph's only
  add_mover(s, 14, 40, 0, 0, 5);                    // leader at 5 m/s
  Fitted f(s);
  auto sl = std::make_unique<BasicSlScene<Cfg>>();
  sl->build(s, *f.line, 0, 0, 100, kSettings);
  // The ego guessed at 15 m/s: its rear axle reaches the leader's grown box
  // (leader rear at 40 - 2.25 - margin + 5 t, less the ego's front reach
  // 3.8 m) at 15 t = 40 - 2.25 - 0.5 - 3.8 + 5 t, t = 3.345 s: sample 34.
  std::array<Scalar, Cfg::kStSamples> s_guess{};
  for (std::size_t k = 0; k < s_guess.size(); ++k) s_guess[k] = 15 * 0.1 * static_cast<double>(k);
  bool skip[Cfg::kMaxDynamicObstacles] = {};
  CHECK(sl->place_dynamic(s_guess, skip) == 1);
  REQUIRE(sl->boxes().size() == 1);
  const auto& b = sl->boxes()[0];
  CHECK(b.obstacle_id == 14);
  CHECK(b.dynamic);
  const double t_meet = 3.4;  // sample 34
  CHECK(b.s_min == doctest::Approx(40 + 5 * t_meet - 2.25 - 0.5 - 3.8).epsilon(1e-6));
  CHECK(sl->nearest_dynamic(skip, -1e9, 1e9) == 1);
  skip[1] = true;
  CHECK(sl->place_dynamic(s_guess, skip) == 0);
  CHECK(sl->boxes().empty());
}

TEST_CASE("curvature bounds: a_lat / v^2 at the guessed speed, never below the road's own curve") {
  Scene s = road_scene(1, 0, 100);  // an arc of radius 100 m: kappa_ref = 0.01
  Fitted f(s);
  BasicCurvatureBounds<Cfg> kb;
  kb.sample_reference(*f.line, 10, 100);
  itp::decision::MotionLimits lim;
  lim.lat_acc_max = 2;
  lim.kappa_max = 0.2;
  lim.a_min = -5;
  std::array<Scalar, Cfg::kStSamples> s_guess{};
  std::array<Scalar, Cfg::kStSamples> v_guess{};
  for (std::size_t k = 0; k < s_guess.size(); ++k) {
    s_guess[k] = 10 * 0.1 * static_cast<double>(k);
    v_guess[k] = 10;
  }
  kb.update_expected(s_guess, v_guess, lim);
  // 2 / 100 = 0.02 > 0.01 + 0.002: the lateral-acceleration bound.
  CHECK(kb.expected.at(50) == doctest::Approx(0.02).epsilon(1e-9));
  for (auto& v : v_guess) v = 20;
  kb.update_expected(s_guess, v_guess, lim);
  // 2 / 400 = 0.005 < 0.012: the road's own curvature plus slack.
  CHECK(kb.expected.at(50) == doctest::Approx(std::fabs(kb.reference.at(50)) + 0.002).epsilon(1e-9));
  CHECK(std::fabs(kb.reference.at(50)) == doctest::Approx(0.01).epsilon(0.02));
  // Reachable at 20 m/s braking at 5 m/s^2 after 0.3 s: at 20 m ahead
  // v_min^2 = 400 - 2 * 5 * (20 - 6) = 260; the bound 2 / 260.
  kb.update_reachable(20, 3.8, lim);
  const double at = kb.reference.s0 + 20;
  CHECK(kb.reach.at(at) == doctest::Approx(std::max(2.0 / 260, std::fabs(kb.reference.at(at)) + 0.002)).epsilon(1e-6));
  CHECK(kb.evasive.at(at) == doctest::Approx(std::max(3.8 / 260, std::fabs(kb.reference.at(at)) + 0.002)).epsilon(1e-6));
  // Where braking can stop the ego (v_min < 1 m/s): the steering limit.
  CHECK(kb.reach.at(kb.reference.s0 + 90) == doctest::Approx(0.2));
}

TEST_CASE("collision check: the first sample whose real footprint overlaps an obstacle") {
  Scene s = road_scene(1, 0);
  add_static(s, 5, 30, 0, 0, 4.0, 2.0);  // x in [28, 32]
  itp::planner::BasicPlan<Cfg> plan;
  for (int k = 0; k < Cfg::kTrajectorySamples; ++k) {
    TrajectoryPoint p;
    p.t = 0.1 * k;
    p.x = 10 * p.t;  // rear axle at 10 m/s; front bumper 3.8 m ahead
    REQUIRE(plan.trajectory.push_back(p));
  }
  const CollisionHit hit = first_collision<Cfg>(s, {}, plan);
  REQUIRE(hit.found());
  CHECK(hit.obstacle == 5);
  // Front at 10 t + 3.8 reaches x = 28 first at t = 2.42: sample 25.
  CHECK(hit.sample == 25);
  s.static_obstacles.clear();
  add_static(s, 6, 30, 1.95 + 1.0 + 0.01, 0, 4.0, 2.0);  // just beside the ego's 1.9 m width
  CHECK_FALSE(first_collision<Cfg>(s, {}, plan).found());
}

TEST_CASE("safe stop: comfortable braking along the reference at the held offset") {
  Scene s = road_scene(1, 0);
  s.ego.state.y = 0.4;
  Fitted f(s);
  BasicSafeStopInput<Cfg> in;
  in.scene = &s;
  in.reference = f.line.get();
  in.comfort_decel = -3;
  FallbackMemory memory;
  auto out = std::make_unique<BasicPlan<Cfg>>();
  safe_stop(in, FallbackReason::kPathQpFailed, memory, *out);
  CHECK(out->status == itp::PlanStatus::kFallback);
  CHECK(out->fallback == FallbackReason::kPathQpFailed);
  REQUIRE(out->trajectory.size() == static_cast<std::size_t>(Cfg::kTrajectorySamples));
  for (const TrajectoryPoint& p : out->trajectory) {
    const double t_stop = 10.0 / 3;
    const double tt = std::min(p.t, t_stop);
    CHECK(p.v == doctest::Approx(std::max(10 - 3 * p.t, 0.0)));
    CHECK(p.x == doctest::Approx(10 * tt - 1.5 * tt * tt).epsilon(1e-6));
    CHECK(p.y == doctest::Approx(0.4).epsilon(1e-6));
  }
  CHECK(memory.holding_l);
  // The next fallback holds the first one's offset even when the ego drifted.
  s.ego.state.y = 0.9;
  safe_stop(in, FallbackReason::kPathQpFailed, memory, *out);
  CHECK(out->trajectory[10].y == doctest::Approx(0.4).epsilon(1e-6));
}

TEST_CASE("safe stop: brakes at the vehicle's limit when comfortable braking would hit a car ahead") {
  Scene s = road_scene(1, 0);
  s.ego.limits.a_min = -8;
  add_static(s, 1, 3.8 + 14 + 2.25, 0);  // rear 14 m ahead of the front bumper at 10 m/s
  Fitted f(s);
  BasicSafeStopInput<Cfg> in;
  in.scene = &s;
  in.reference = f.line.get();
  FallbackMemory memory;
  auto out = std::make_unique<BasicPlan<Cfg>>();
  safe_stop(in, FallbackReason::kCollision, memory, *out);
  // 3 m/s^2 needs 16.7 m, 8 m/s^2 stops in 6.25 m.
  CHECK(out->trajectory[1].a == doctest::Approx(-8));
  CHECK_FALSE(first_collision<Cfg>(s, {}, *out).found());
}

TEST_CASE("safe stop: along a curved last plan it brakes hard enough to keep lat_acc_max") {
  // The last ok plan: 10 m straight, then an arc of R = 15 m, planned at 6 m/s.
  // The ego is on it at 11 m/s: comfortable braking (3 m/s^2) reaches the arc
  // at v^2 = 61, 4.1 m/s^2 across; 4 m/s^2 reaches it at v^2 = 41, 2.7 m/s^2.
  auto previous = std::make_unique<BasicPlan<Cfg>>();
  for (int k = 0; k < Cfg::kTrajectorySamples; ++k) {
    TrajectoryPoint p;
    p.t = 0.1 * k;
    p.s = 6 * p.t;
    p.v = 6;
    if (p.s <= 10) {
      p.x = p.s;
    } else {
      const double th = (p.s - 10) / 15;
      p.x = 10 + 15 * std::sin(th);
      p.y = 15 * (1 - std::cos(th));
      p.heading = th;
      p.kappa = 1.0 / 15;
    }
    REQUIRE(previous->trajectory.push_back(p));
  }
  Scene s = road_scene(1, 0);
  s.ego.state.v = 11;
  s.ego.limits.lat_acc_max = 3;
  s.ego.limits.a_min = -6;
  Fitted f(s);
  BasicSafeStopInput<Cfg> in;
  in.scene = &s;
  in.reference = f.line.get();
  in.previous = previous.get();
  in.previous_time = 0;
  in.now = 0.2;
  in.comfort_decel = -3;
  FallbackMemory memory;
  auto out = std::make_unique<BasicPlan<Cfg>>();
  safe_stop(in, FallbackReason::kPathQpFailed, memory, *out);
  CHECK(out->trajectory[1].a == doctest::Approx(-4));
  double worst = 0;
  for (const TrajectoryPoint& p : out->trajectory) {
    worst = std::max(worst, p.v * p.v * std::fabs(p.kappa));
  }
  CHECK(worst <= 3.0);
  CHECK(out->trajectory.back().y > 0.5);  // it followed the arc (0.86 m), not the reference
}

TEST_CASE("safe stop: invalid input stops in place from a standstill, whatever it was sent") {
  auto out = std::make_unique<BasicPlan<Cfg>>();
  out->status = itp::PlanStatus::kInvalidInput;
  BasicSafeStopInput<Cfg> in;  // no scene
  FallbackMemory memory;
  safe_stop(in, FallbackReason::kNone, memory, *out);
  CHECK(out->status == itp::PlanStatus::kInvalidInput);
  REQUIRE(out->trajectory.size() == static_cast<std::size_t>(Cfg::kTrajectorySamples));
  for (const TrajectoryPoint& p : out->trajectory) {
    CHECK(p.v == 0);
    CHECK(std::isfinite(p.x));
  }
}

namespace {

// A three-lane road (-1.75 .. 8.75 m) with one car in the middle lane 40 m
// ahead: the corridor passes it on the left or on the right.
struct OneCarAhead {
  using Arena = typename itp::decision::BasicDecisionStage<Cfg>::QpArena;
  std::unique_ptr<Arena> arena = std::make_unique<Arena>();
  std::unique_ptr<itp::decision::BasicDecisionStage<Cfg>> stage =
      std::make_unique<itp::decision::BasicDecisionStage<Cfg>>(*arena);
  std::vector<itp::geometry::SlBox> boxes;
  OneCarAhead(bool dynamic) {
    itp::decision::BasicRoadSl<Cfg> road;
    road.left = itp::decision::BasicLateralProfile<Cfg>::constant(8.75);
    road.right = itp::decision::BasicLateralProfile<Cfg>::constant(-1.75);
    road.lane_width = 3.5;
    road.target_lane_offset = 3.5;
    itp::geometry::SlBox b{38, 46, 2.4, 4.6, 7, dynamic};
    boxes.push_back(b);
    itp::decision::ConvexSpaceParams cp;
    cp.s_start = 0;
    cp.s_end = 100;
    cp.ego_l = 3.5;
    itp::decision::BasicCoarseInput<Cfg> ci;
    ci.l_init = 3.5;
    ci.v_init = 10;
    ci.l_ref = 3.5;
    REQUIRE(stage->run(road, boxes, cp, ci, itp::decision::DecisionWeights{}) ==
            itp::decision::DecisionStatus::kOk);
  }
  // The side of the car the kept decision `i` passes it on.
  LateralSide side(int i) const {
    const auto s = itp::decision::side_of(stage->space(), stage->decisions().kept[static_cast<std::size_t>(i)], boxes[0]);
    return s == itp::decision::Side::kLeft ? LateralSide::kLeft
           : s == itp::decision::Side::kRight ? LateralSide::kRight : LateralSide::kNone;
  }
};

}  // namespace

TEST_CASE("decision choice: ranked by decision cost; keeping last plan's side earns the hysteresis bonus") {
  const OneCarAhead scene(false);
  std::array<int, Cfg::kKeptDecisions> order{};
  const int n = rank_decisions(*scene.stage, scene.boxes, PreviousSides{}, kSettings, 3.5, order);
  REQUIRE(n >= 2);
  for (int i = 1; i < n; ++i) {  // ascending decision cost without a previous plan
    CHECK(scene.stage->coarse(static_cast<std::size_t>(order[static_cast<std::size_t>(i - 1)])).decision_cost <=
          scene.stage->coarse(static_cast<std::size_t>(order[static_cast<std::size_t>(i)])).decision_cost);
  }
  // Last plan passed the car on the side the cheapest decision does not: with
  // the bonus that side's best decision comes first unless it costs more
  // than the bonus more.
  const LateralSide first_side = scene.side(order[0]);
  REQUIRE(first_side != LateralSide::kNone);
  const LateralSide other = first_side == LateralSide::kLeft ? LateralSide::kRight : LateralSide::kLeft;
  const ObstacleDecision previous[1] = {{7, other, itp::speed::Longitudinal::kIgnore, false}};
  std::array<int, Cfg::kKeptDecisions> with{};
  REQUIRE(rank_decisions(*scene.stage, scene.boxes, PreviousSides{previous}, kSettings, 3.5, with) == n);
  double best_other = 1e300;
  for (int i = 0; i < n; ++i) {
    if (scene.side(order[static_cast<std::size_t>(i)]) == other) {
      best_other = std::min(best_other, static_cast<double>(scene.stage->coarse(static_cast<std::size_t>(order[static_cast<std::size_t>(i)])).decision_cost));
    }
  }
  const double best = scene.stage->coarse(static_cast<std::size_t>(order[0])).decision_cost;
  CHECK(scene.side(with[0]) == (best_other - kSettings.hysteresis < best ? other : first_side));
}

TEST_CASE("decision choice: passing a moving obstacle on the other side than last plan comes last") {
  const OneCarAhead scene(true);
  std::array<int, Cfg::kKeptDecisions> order{};
  const int n = rank_decisions(*scene.stage, scene.boxes, PreviousSides{}, kSettings, 3.5, order);
  REQUIRE(n >= 2);
  const LateralSide first_side = scene.side(order[0]);
  const LateralSide other = first_side == LateralSide::kLeft ? LateralSide::kRight : LateralSide::kLeft;
  const ObstacleDecision previous[1] = {{7, other, itp::speed::Longitudinal::kIgnore, true}};
  std::array<int, Cfg::kKeptDecisions> with{};
  REQUIRE(rank_decisions(*scene.stage, scene.boxes, PreviousSides{previous}, kSettings, 3.5, with) == n);
  // Every decision that keeps `other` (or does not pass the car) precedes
  // every one that passes it on first_side.
  bool seen_flip = false;
  for (int i = 0; i < n; ++i) {
    const bool flip = scene.side(with[static_cast<std::size_t>(i)]) == first_side;
    CHECK_FALSE((seen_flip && !flip));
    seen_flip = seen_flip || flip;
  }
  CHECK(scene.side(with[0]) != first_side);
}

TEST_CASE("decision choice: the plan records the chosen corridor's sides and the ST decisions") {
  const OneCarAhead scene(true);
  auto out = std::make_unique<BasicPlan<Cfg>>();
  itp::speed::BasicStDecision<Cfg> st[2];
  st[0].id = 7;
  st[0].decision = itp::speed::Longitudinal::kOvertake;
  st[1].id = 9;  // only in the ST graph (left out of the convex space)
  st[1].decision = itp::speed::Longitudinal::kYield;
  record_decisions<Cfg>(*scene.stage, 0, scene.boxes, st, *out);
  REQUIRE(out->decisions.size() == 2);
  CHECK(out->decisions[0].obstacle == 7);
  CHECK(out->decisions[0].lateral == scene.side(0));
  CHECK(out->decisions[0].longitudinal == itp::speed::Longitudinal::kOvertake);
  CHECK(out->decisions[1].obstacle == 9);
  CHECK(out->decisions[1].lateral == LateralSide::kNone);
  CHECK(out->decisions[1].longitudinal == itp::speed::Longitudinal::kYield);
  record_decisions<Cfg>(*scene.stage, -1, scene.boxes, st, *out);
  CHECK(out->decisions.empty());
}
