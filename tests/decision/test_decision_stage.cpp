#include <doctest/doctest.h>

#include <cmath>
#include <memory>

#include "heap_guard.hpp"
#include "itp/decision/decision_stage.hpp"
#include "sl_scenes.hpp"

using namespace itp::decision;
using namespace decision_test;

namespace {

CoarseInput input(Scalar l_init = 0, Scalar v = 10) {
  CoarseInput in;
  in.l_init = l_init;
  in.v_init = v;
  in.l_ref = 0;
  return in;
}

struct Stage {
  std::unique_ptr<DecisionStage::QpArena> arena = std::make_unique<DecisionStage::QpArena>();
  std::unique_ptr<DecisionStage> stage = std::make_unique<DecisionStage>(*arena);
  DecisionStatus status = DecisionStatus::kInvalidInput;
  // Its own arena: the re-solves leave the stage's hold on the shared one.
  std::unique_ptr<DecisionStage::QpArena> again_arena = std::make_unique<DecisionStage::QpArena>();
  std::unique_ptr<CoarseEvaluator> evaluator = std::make_unique<CoarseEvaluator>(*again_arena);
  std::unique_ptr<CoarseResult> result = std::make_unique<CoarseResult>();

  // Kept decision i's coarse samples (the stage keeps only its score).
  const CoarseResult& coarse(std::size_t i) {
    stage->evaluate_again(i, *evaluator, *result);
    return *result;
  }
};

Stage run(const RoadSl& r, const std::vector<SlBox>& boxes, const CoarseInput& in) {
  Stage s;
  test_support::HeapGuard guard;
  s.status = s.stage->run(r, boxes, params(in.l_init), in, DecisionWeights{});
  return s;
}

// The coarse solution respects every constraint of eq. (3) and the time rows.
void check_coarse_feasible(const CoarseResult& c, const CoarseInput& in) {
  REQUIRE(itp::qp::is_usable(c.status));
  CHECK(c.l[0] == doctest::Approx(in.l_init));
  CHECK(c.t[0] == doctest::Approx(0));
  for (int i = 0; i < c.samples; ++i) {
    const auto u = static_cast<std::size_t>(i);
    if (i > 0) {
      CHECK(c.l[u] >= c.l_lb[u] - 1e-6);
      CHECK(c.l[u] <= c.l_ub[u] + 1e-6);
      CHECK(c.t[u] - c.t[u - 1] >= c.ds / in.limits.speed_limit - 1e-6);
    }
    CHECK(c.t[u] >= c.t_lb[u] - 1e-6);
  }
}

}  // namespace

TEST_CASE("earliest arrival follows the kinematic limits") {
  CoarseInput in = input(0, 0);
  in.limits.speed_limit = 10;
  in.limits.a_max = 2;
  std::array<Scalar, itp::DefaultConfig::kCoarseSamples> t{};
  const Scalar ds = 100.0 / (itp::DefaultConfig::kCoarseSamples - 1);
  earliest_arrival(in, 0, ds, itp::DefaultConfig::kCoarseSamples, false, t.data());
  // From rest at 2 m/s² the ego reaches 10 m/s after 25 m and 5 s, then cruises:
  // t(100 m) = 5 + 75/10 = 12.5 s.
  CHECK(t[0] == 0);
  CHECK(t.back() == doctest::Approx(12.5).epsilon(0.01));
  const std::size_t i25 = 5;  // s = 26.3 m
  CHECK(t[i25] == doctest::Approx(5.0 + (5 * ds - 25) / 10).epsilon(0.02));
}

TEST_CASE("free road: one decision, kept in lane, at the speed limit") {
  const CoarseInput in = input(0, 16.7);
  auto s = run(road(-1.75, 5.25), {}, in);
  REQUIRE(s.status == DecisionStatus::kOk);
  REQUIRE(s.stage->best() == 0);
  const CoarseResult& c = s.coarse(0);
  check_coarse_feasible(c, in);
  for (int i = 0; i < c.samples; ++i) {
    CHECK(std::fabs(c.l[static_cast<std::size_t>(i)]) < 1e-6);
  }
  CHECK(c.t.back() == doctest::Approx(100 / 16.7).epsilon(0.01));
  CHECK(c.kappa_mean == doctest::Approx(0).epsilon(1e-9));
  CHECK(c.a_lon_mean < 0.05);
}

TEST_CASE("one obstacle in lane: both sides evaluated, the roomier wins, swerving costs path and dynamic terms") {
  const CoarseInput in = input(0, 10);
  const std::vector<SlBox> boxes{box(40, 45, -0.9, 0.9, 1)};
  auto s = run(road(-5.25, 5.25), boxes, in);
  REQUIRE(s.status == DecisionStatus::kOk);
  REQUIRE(s.stage->decisions().kept.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    check_coarse_feasible(s.coarse(i), in);
    CHECK(s.stage->coarse(i).path_cost > 0);
  }
  // Symmetric room: the geometric tie is broken by zone order; what matters is
  // that the chosen corridor clears the obstacle on the side it names.
  const auto best = static_cast<std::size_t>(s.stage->best());
  const Side side = side_of(s.stage->space(), s.stage->decisions().kept[best], boxes[0]);
  const CoarseResult& c = s.coarse(best);
  for (int i = 0; i < c.samples; ++i) {
    const auto u = static_cast<std::size_t>(i);
    if (c.s[u] >= 40 && c.s[u] <= 45) {
      if (side == Side::kLeft) {
        CHECK(c.l[u] >= 0.9 + 0.95 + 0.2 - 1e-6);
      } else {
        CHECK(c.l[u] <= -0.9 - 0.95 - 0.2 + 1e-6);
      }
    }
  }
}

TEST_CASE("an obstacle blocking every lane: the decision is blocked and the coarse plan stops before it") {
  const CoarseInput in = input(0, 10);
  const std::vector<SlBox> boxes{box(50, 55, -3, 7, 1)};
  auto s = run(road(-1.75, 5.25), boxes, in);
  REQUIRE(s.status == DecisionStatus::kBlocked);
  const CoarseResult& c = s.coarse(static_cast<std::size_t>(s.stage->best()));
  check_coarse_feasible(c, in);
  CHECK(c.s.back() <= 50 - in.stop_margin + 1e-9);
}

TEST_CASE("a target lane to the left: the decision that ends in it wins") {
  CoarseInput in = input(0, 10);
  in.l_ref = 3.5;
  const std::vector<SlBox> boxes{box(40, 45, 1.0, 2.5, 5)};
  RoadSl r = road(-3.5, 7.0, 3.5);
  auto s = run(r, boxes, in);
  REQUIRE(s.status == DecisionStatus::kOk);
  const auto best = static_cast<std::size_t>(s.stage->best());
  CHECK(side_of(s.stage->space(), s.stage->decisions().kept[best], boxes[0]) == Side::kLeft);
  CHECK(s.coarse(best).l.back() == doctest::Approx(3.5).epsilon(0.05));
}

TEST_CASE("no zone for the ego gives no decision, never a crash") {
  const CoarseInput in = input(0, 10);
  const std::vector<SlBox> wall{box(-5, 10, -10, 10, 1)};
  auto s = run(road(-1.75, 5.25), wall, in);
  CHECK(s.status == DecisionStatus::kNoDecision);
  CHECK(s.stage->best() == -1);
}

TEST_CASE("a decision run within a budget: no more coarse QPs, iterations and tree nodes than it allows") {
  const CoarseInput in = input(0, 10);
  const std::vector<SlBox> boxes{box(40, 45, -0.9, 0.9, 1)};
  const std::unique_ptr<DecisionStage::QpArena> arena = std::make_unique<DecisionStage::QpArena>();
  const std::unique_ptr<DecisionStage> stage = std::make_unique<DecisionStage>(*arena);
  DecisionWork work;
  {
    test_support::HeapGuard guard;
    // Budget for one coarse QP: the second decision stays unevaluated (not usable).
    const DecisionStatus st = stage->run(road(-5.25, 5.25), boxes, params(0), in, DecisionWeights{},
                                         DecisionBudget{4096, 1, 1000}, itp::TickSource{}, work);
    CHECK(st == DecisionStatus::kOk);
  }
  REQUIRE(stage->decisions().kept.size() == 2);
  CHECK(work.coarse_qps == 1);
  CHECK(work.budget_out);
  CHECK(itp::qp::is_usable(stage->coarse(0).status));
  CHECK_FALSE(itp::qp::is_usable(stage->coarse(1).status));
  CHECK(stage->best() == 0);
  // No coarse QP left: no decision, and the run says that the budget cut it short.
  CHECK(stage->run(road(-5.25, 5.25), boxes, params(0), in, DecisionWeights{}, DecisionBudget{4096, 0, 1000},
                   itp::TickSource{}, work) == DecisionStatus::kNoDecision);
  CHECK(work.coarse_qps == 0);
  CHECK(work.budget_out);
  // A tree-node budget caps the search.
  stage->run(road(-5.25, 5.25), boxes, params(0), in, DecisionWeights{}, DecisionBudget{2, 20, 1000},
             itp::TickSource{}, work);
  CHECK(work.tree_nodes <= 2);
  // An iteration budget caps the coarse QPs' iterations in all.
  stage->run(road(-5.25, 5.25), boxes, params(0), in, DecisionWeights{}, DecisionBudget{4096, 20, 1},
             itp::TickSource{}, work);
  CHECK(work.coarse_iterations <= 1);
}

TEST_CASE("the kept scores are the run's evaluations: a cold evaluation again gives the same status, costs and end") {
  // Two decisions around an obstacle and one blocked-lane case: the stage
  // keeps only scores; evaluate_again solves each coarse QP cold (the run
  // hotstarted them), to the same optimum within the QP's tolerance.
  const CoarseInput in = input(0, 10);
  for (const std::vector<SlBox>& boxes : {std::vector<SlBox>{box(40, 45, -0.9, 0.9, 1)},
                                          std::vector<SlBox>{box(30, 34, -1.2, 0.4, 1), box(60, 66, 0.8, 3.0, 2)}}) {
    auto s = run(road(-5.25, 5.25), boxes, in);
    REQUIRE(s.status == DecisionStatus::kOk);
    REQUIRE(s.stage->decisions().kept.size() >= 2);
    for (std::size_t i = 0; i < s.stage->decisions().kept.size(); ++i) {
      const itp::decision::CoarseScore& kept = s.stage->coarse(i);
      const CoarseResult& again = s.coarse(i);
      REQUIRE(again.status == kept.status);
      if (!itp::qp::is_usable(kept.status)) continue;
      CHECK(again.samples == kept.samples);
      CHECK(again.decision_cost == doctest::Approx(kept.decision_cost).epsilon(1e-6));
      CHECK(again.path_cost == doctest::Approx(kept.path_cost).epsilon(1e-6));
      CHECK(again.l[static_cast<std::size_t>(again.samples - 1)] == doctest::Approx(kept.l_end).epsilon(1e-6));
      CHECK(again.l_end == doctest::Approx(kept.l_end).epsilon(1e-6));
    }
  }
  CoarseResult out;
  auto s = run(road(-5.25, 5.25), {}, in);
  s.stage->evaluate_again(99, *s.evaluator, out);  // no such decision
  CHECK(out.status == itp::qp::QpStatus::kInvalidInput);
}
