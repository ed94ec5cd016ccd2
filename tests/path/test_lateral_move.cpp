#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "itp/decision/decision_stage.hpp"
#include "itp/path/lateral_move.hpp"
#include "itp/path/path_optimizer.hpp"
#include "itp/qp/solver.hpp"
#include "sl_scenes.hpp"

using namespace itp::decision;
using namespace itp::path;
using namespace decision_test;

TEST_CASE("lateral_move_length: the closed forms") {
  // Two arcs while their steepest slope kappa L / 2 stays within the bound.
  CHECK(lateral_move_length(0.5, 0.2, 0.5) == doctest::Approx(2 * std::sqrt(0.5 / 0.2)));
  // Ramps of 0.5 / 0.2 = 2.5 m at each end move 2 * 0.625 m; the rest at slope 0.5.
  CHECK(lateral_move_length(2.15, 0.2, 0.5) == doctest::Approx(5.0 + (2.15 - 1.25) / 0.5));
  // Continuous where the two meet: e = slope^2 / kappa.
  CHECK(lateral_move_length(1.25, 0.2, 0.5) == doctest::Approx(5.0));
  CHECK(lateral_move_length(0.0, 0.2, 0.5) == 0.0);
  CHECK(std::isinf(lateral_move_length(1.0, 0.0, 0.5)));
}

// The path QP (quintic blocks, its l'' and l' rows) as the reference: a
// corridor that holds the ego's centre within [e, e + 5 cm] from s = L on is
// feasible from rest at l = 0 when L exceeds lateral_move_length (plus the
// QP's 1 m sample spacing), and infeasible well below it. The path
// optimizer builds the QP; the general solver settles it without the
// planner's run-time iteration cap (so "infeasible" is the QP's, never a cap's).
TEST_CASE("lateral_move_length against the path QP: the move fits in it, and not in much less") {
  using Dims = PathOptimizer::PathDims;
  auto space = std::make_unique<ConvexSpace>();
  auto set = std::make_unique<DecisionSet>();
  auto arena = std::make_unique<PathOptimizer::QpArena>();
  auto opt = std::make_unique<PathOptimizer>(*arena);
  auto problem = std::make_unique<itp::qp::QpProblem<Dims>>();
  auto ws = std::make_unique<itp::qp::QpWorkspace<Dims>>();
  auto res = std::make_unique<itp::qp::QpResult<Dims>>();
  const auto feasible = [&](double e, double kappa, double from) {
    PathInput in;
    in.kappa_max = kappa;
    in.front_reach = 0;  // the centre alone: both bumper rows are l
    in.rear_reach = 0;
    const double hw = 0.5 * in.vehicle_width;
    const std::vector<SlBox> boxes{box(from, 100, -1.75, e - hw, 1), box(from, 100, e + 0.05 + hw, 5.25, 2)};
    REQUIRE(build_convex_space(road(-1.75, 5.25), boxes, params(0), *space) == ConvexSpaceStatus::kOk);
    enumerate_decisions(*space, GeometricWeights{}, *set);
    REQUIRE(set->kept.size() == 1);
    PathResult result;
    opt->solve(*space, set->kept[0], in, PathWeights{}, result);
    *problem = opt->problem();
    const itp::qp::QpStatus st = itp::qp::solve_cold(*problem, *ws, itp::qp::QpSettings<Scalar>{}, *res);
    REQUIRE((st == itp::qp::QpStatus::kOptimal || st == itp::qp::QpStatus::kInfeasible));
    return st == itp::qp::QpStatus::kOptimal;
  };
  // Two arcs (kappa 0.05), and ramps with a run at |l'| = 0.5 between (kappa 0.2);
  // every length past the first block (5 m), whose rows admit the start.
  const double cases[][2] = {{0.5, 0.03}, {1.25, 0.05}, {3.0, 0.05}, {2.15, 0.2}, {3.0, 0.2}};
  for (const auto& c : cases) {
    const double e = c[0], kappa = c[1];
    const double length = lateral_move_length(e, kappa, PathInput{}.dl_max);
    CAPTURE(e);
    CAPTURE(kappa);
    CAPTURE(length);
    REQUIRE(0.75 * length > 5.0);
    CHECK(feasible(e, kappa, std::ceil(length) + 1.0));
    CHECK_FALSE(feasible(e, kappa, 0.75 * length));
  }
}
