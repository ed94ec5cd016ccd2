// The planner's QP shapes: path (63 vars, 300 rows), speed (45, 210) and
// coarse (40 vars, bounds + 19 rows), in double and float, without heap.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "heap_guard.hpp"
#include "default_qp_shapes.hpp"
#include "planner_qps.hpp"
#include "qp_test_util.hpp"

using namespace itp::qp;

namespace {

template <class D>
struct Instance {
  QpProblem<D> problem;
  QpWorkspace<D> ws;
  QpResult<D> result;
  QpSettings<typename D::Scalar> settings;
};

// Active rows / bounds in the result's working set.
template <class D>
int active_rows(const QpResult<D>& r) {
  int k = 0;
  for (int i = 0; i < r.working_set.size; ++i) k += r.working_set.entries[i].is_bound ? 0 : 1;
  return k;
}

template <class D>
void solve_checked(Instance<D>& in, double kkt_tol) {
  QpStatus st;
  {
    test_support::HeapGuard guard;
    st = solve_cold(in.problem, in.ws, in.settings, in.result);
  }
  REQUIRE(st == QpStatus::kOptimal);
  const auto kkt = kkt_residual(in.problem, in.result);
  CAPTURE(static_cast<double>(kkt.stationarity));
  CAPTURE(static_cast<double>(kkt.primal));
  CAPTURE(static_cast<double>(kkt.complementarity));
  // relative to the data scale
  double scale = 1.0;
  for (int j = 0; j < in.problem.n; ++j) scale = std::max(scale, std::abs(static_cast<double>(in.problem.g[j])));
  CAPTURE(scale);
  CHECK(static_cast<double>(kkt.max()) < kkt_tol * scale);
}

}  // namespace

TEST_CASE("path QP: corridor pinch around an obstacle, double and float") {
  auto d = std::make_unique<Instance<PathQp<double>>>();
  planner_qps::PathScenario sc;
  REQUIRE(planner_qps::build_path_qp(d->problem, sc));
  CHECK(d->problem.n == 63);
  CHECK(d->problem.m == 300);
  solve_checked(*d, 1e-7);
  const int rows = active_rows(d->result);
  CAPTURE(rows);
  CHECK(rows >= 10);
  CHECK(rows <= 40);
  // The path passes the obstacle on the left: l + 0.2 l' >= 2.45 at s = 47.5 m.
  const auto& x = d->result.x;
  CHECK(x[3 * 9] + 0.2 * x[3 * 9 + 1] >= 2.45 - 1e-6);

  auto f = std::make_unique<Instance<PathQp<float>>>();
  REQUIRE(planner_qps::build_path_qp(f->problem, sc));
  solve_checked(*f, 1e-3);
  for (int j = 0; j < 63; ++j) CHECK(f->result.x[j] == doctest::Approx(x[j]).epsilon(2e-2).scale(1.0));
}

TEST_CASE("path QP: an impossible swerve is infeasible") {
  auto d = std::make_unique<Instance<PathQp<double>>>();
  planner_qps::PathScenario sc;
  sc.obstacle_s0 = 4.0;  // 3.25 m to the left within 4 m with |l''| <= 0.1
  REQUIRE(planner_qps::build_path_qp(d->problem, sc));
  test_support::HeapGuard guard;
  CHECK(solve_cold(d->problem, d->ws, d->settings, d->result) == QpStatus::kInfeasible);
}

TEST_CASE("speed QP: following a slower vehicle") {
  auto d = std::make_unique<Instance<SpeedQp<double>>>();
  planner_qps::SpeedScenario sc;
  REQUIRE(planner_qps::build_speed_qp(d->problem, sc));
  CHECK(d->problem.n == 45);
  CHECK(d->problem.m == 210);
  solve_checked(*d, 1e-6);
  CHECK(active_rows(d->result) >= 3);
  auto f = std::make_unique<Instance<SpeedQp<float>>>();
  REQUIRE(planner_qps::build_speed_qp(f->problem, sc));
  solve_checked(*f, 1e-3);
}

TEST_CASE("coarse decision QP") {
  auto d = std::make_unique<Instance<CoarseQp<double>>>();
  planner_qps::CoarseScenario sc;
  REQUIRE(planner_qps::build_coarse_qp(d->problem, sc));
  CHECK(d->problem.n == 40);
  solve_checked(*d, 1e-8);
  CHECK(d->result.working_set.size >= 4);
  auto f = std::make_unique<Instance<CoarseQp<float>>>();
  REQUIRE(planner_qps::build_coarse_qp(f->problem, sc));
  solve_checked(*f, 1e-3);
}

TEST_CASE("workspace sizes of the planner instances (recorded in docs/qp.md)") {
  std::printf("sizeof QpWorkspace/QpProblem/QpResult (double): path %zu/%zu/%zu speed %zu/%zu/%zu coarse %zu/%zu/%zu\n",
              sizeof(QpWorkspace<PathQp<double>>), sizeof(QpProblem<PathQp<double>>),
              sizeof(QpResult<PathQp<double>>), sizeof(QpWorkspace<SpeedQp<double>>),
              sizeof(QpProblem<SpeedQp<double>>), sizeof(QpResult<SpeedQp<double>>),
              sizeof(QpWorkspace<CoarseQp<double>>), sizeof(QpProblem<CoarseQp<double>>),
              sizeof(QpResult<CoarseQp<double>>));
  std::printf("sizeof QpWorkspace (float): path %zu speed %zu coarse %zu\n",
              sizeof(QpWorkspace<PathQp<float>>), sizeof(QpWorkspace<SpeedQp<float>>),
              sizeof(QpWorkspace<CoarseQp<float>>));
  static_assert(sizeof(QpWorkspace<PathQp<double>>) < 64 * 1024,
                "path QP workspace budget: 64 KiB");
  CHECK(sizeof(QpWorkspace<PathQp<float>>) < sizeof(QpWorkspace<PathQp<double>>));
}
