// Warm start from a working set and hotstart on a sequence of QPs with the
// same H and A: same solution as a cold solve, in fewer iterations, no heap.
#include <doctest/doctest.h>

#include <memory>
#include <random>

#include "heap_guard.hpp"
#include "planner_qps.hpp"
#include "qp_test_util.hpp"

using namespace itp::qp;

namespace {

using PathD = PathQpDims<double, itp::DefaultConfig>;
using BigD = QpDims<double, 80, 160, 6, 4>;

template <class D>
struct Pair {
  QpProblem<D> problem;
  QpWorkspace<D> ws_cold, ws_warm;
  QpResult<D> cold, warm;
  QpSettings<typename D::Scalar> settings;
};

template <class D>
double x_diff(const QpResult<D>& a, const QpResult<D>& b, int n) {
  double d = 0.0;
  for (int j = 0; j < n; ++j) d = std::max(d, std::abs(static_cast<double>(a.x[j] - b.x[j])));
  return d;
}

}  // namespace

TEST_CASE("warm start from the previous working set: same solution, fewer iterations") {
  auto t = std::make_unique<Pair<BigD>>();
  std::mt19937 rng(31);
  std::normal_distribution<double> gauss(0.0, 1.0);
  long cold_total = 0, warm_total = 0;
  for (int rep = 0; rep < 10; ++rep) {
    qp_test::BuildOptions o;
    o.n = 30 + 5 * rep;
    o.m = 2 * o.n;
    o.bandwidth = 4;
    o.max_row_nnz = 6;
    o.p_row_active = 0.3;
    qp_test::build_random(t->problem, o, rng);
    REQUIRE(solve_cold(t->problem, t->ws_warm, t->settings, t->warm) == QpStatus::kOptimal);
    const WorkingSet<BigD> previous = t->warm.working_set;
    // A nearby QP: perturbed gradient and bounds.
    for (int j = 0; j < o.n; ++j) t->problem.g[j] += 0.01 * gauss(rng);
    for (int r = 0; r < o.m; ++r) {
      t->problem.uba[r] += 0.005 * std::abs(gauss(rng));
      t->problem.lba[r] -= 0.005 * std::abs(gauss(rng));
    }
    REQUIRE(solve_cold(t->problem, t->ws_cold, t->settings, t->cold) == QpStatus::kOptimal);
    {
      test_support::HeapGuard guard;
      REQUIRE(solve_warm(t->problem, t->ws_warm, t->settings, previous, t->warm) ==
              QpStatus::kOptimal);
    }
    CAPTURE(rep);
    CHECK(x_diff(t->cold, t->warm, o.n) < 1e-8);
    CHECK(t->warm.iterations <= t->cold.iterations);
    cold_total += t->cold.iterations;
    warm_total += t->warm.iterations;
  }
  CHECK(warm_total * 3 < cold_total);
}

TEST_CASE("warm start from an arbitrary (wrong) working set still finds the optimum") {
  auto t = std::make_unique<Pair<BigD>>();
  std::mt19937 rng(32);
  for (int rep = 0; rep < 10; ++rep) {
    qp_test::BuildOptions o;
    o.n = 20 + rep;
    o.m = 40;
    o.bandwidth = 3;
    o.max_row_nnz = 4;
    o.p_row_active = 0.3;
    const auto c = qp_test::build_random(t->problem, o, rng);
    WorkingSet<BigD> junk;
    for (int k = 0; k < 25; ++k) {
      junk.push(static_cast<int>(rng() % 45), rng() % 3 == 0, (rng() % 2) ? 1 : -1);
    }
    REQUIRE(solve_warm(t->problem, t->ws_warm, t->settings, junk, t->warm) == QpStatus::kOptimal);
    CHECK(qp_test::max_abs_diff(t->warm, c.x, o.n) < 1e-6 * (1.0 + qp_test::max_abs(c.x)));
  }
}

TEST_CASE("hotstart on a replanning sequence of path QPs") {
  auto t = std::make_unique<Pair<PathD>>();
  planner_qps::PathScenario sc;
  REQUIRE(planner_qps::build_path_qp(t->problem, sc));
  REQUIRE(solve_cold(t->problem, t->ws_warm, t->settings, t->warm) == QpStatus::kOptimal);
  long cold_total = 0, hot_total = 0;
  for (int step = 1; step <= 12; ++step) {
    // The ego moves on: new initial state and the obstacle edge drifts.
    sc.init_l = 0.05 * step;
    sc.init_dl = 0.01 * (step % 3);
    sc.obstacle_left = 1.5 + 0.03 * step;
    REQUIRE(planner_qps::build_path_qp(t->problem, sc));
    REQUIRE(solve_cold(t->problem, t->ws_cold, t->settings, t->cold) == QpStatus::kOptimal);
    {
      test_support::HeapGuard guard;
      REQUIRE(solve_hot(t->problem, t->ws_warm, t->settings, t->warm) == QpStatus::kOptimal);
    }
    CAPTURE(step);
    CHECK(x_diff(t->cold, t->warm, t->problem.n) < 1e-8);
    CHECK(std::abs(t->cold.objective - t->warm.objective) < 1e-9 * (1.0 + std::abs(t->cold.objective)));
    cold_total += t->cold.iterations;
    hot_total += t->warm.iterations;
  }
  CHECK(hot_total * 2 < cold_total);
}

TEST_CASE("hotstart is refused for a different size and before any factorisation") {
  auto t = std::make_unique<Pair<BigD>>();
  std::mt19937 rng(1);
  qp_test::BuildOptions o;
  o.n = 10;
  o.m = 10;
  qp_test::build_random(t->problem, o, rng);
  CHECK(solve_hot(t->problem, t->ws_cold, t->settings, t->cold) == QpStatus::kNotFactored);
  REQUIRE(solve_cold(t->problem, t->ws_cold, t->settings, t->cold) == QpStatus::kOptimal);
  t->problem.m = 9;
  CHECK(solve_hot(t->problem, t->ws_cold, t->settings, t->cold) == QpStatus::kNotFactored);
}
