// The violation scan skips rows by a certificate (solver.hpp, most_violated):
// row_cert[r] minus the path length x has travelled in the row's blocks since
// must stay a lower bound of the row's scaled slack at the current iterate.
// Checked here against a from-scratch computation in long double, at every
// iteration (the solve is stopped after k = 1, 2, ... iterations), for cold,
// warm and hot starts, in double and float. The per-row block ranges are
// checked against the column indices.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include "heap_guard.hpp"
#include "planner_qps.hpp"
#include "qp_test_util.hpp"

using namespace itp::qp;

namespace {

template <class D>
struct Instance {
  QpProblem<D> problem;
  QpProblem<D> next;
  QpWorkspace<D> ws;
  QpResult<D> result;
  QpSettings<typename D::Scalar> settings;
};

// From-scratch check of the workspace's scan bookkeeping at its current x.
// Returns the number of rows whose certificate is finite (i.e. that a scan
// could skip), so that callers can see the check is not vacuous.
template <class D>
int check_certificates(const QpProblem<D>& p, const QpWorkspace<D>& ws) {
  using S = typename D::Scalar;
  using W = QpWorkspace<D>;
  // Prefix sums of the block path lengths, recomputed here.
  long double prefix[W::kScanBlocks + 1];
  prefix[0] = 0.0L;
  const int nb = (p.n + W::kScanBlock - 1) >> W::kScanBlockShift;
  for (int b = 0; b < nb; ++b) {
    REQUIRE(ws.path_len[b] >= S(0));
    prefix[b + 1] = prefix[b] + static_cast<long double>(ws.path_len[b]);
  }
  // Slack of a row in the worst precision the solver works in; the bound
  // is only meaningful to the primal tolerance, so allow that much.
  const long double tol = static_cast<long double>(QpSettings<S>{}.primal_tolerance);
  int finite = 0;
  for (int r = 0; r < p.m; ++r) {
    const int nnz = p.a_nnz[r];
    const int first = nnz > 0 ? p.a_col[r][0] >> W::kScanBlockShift : 0;
    const int end = nnz > 0 ? (p.a_col[r][nnz - 1] >> W::kScanBlockShift) + 1 : 0;
    REQUIRE(ws.row_first_block[r] == first);
    REQUIRE(ws.row_end_block[r] == end);
    long double ax = 0.0L, n2 = 0.0L;
    for (int k = 0; k < nnz; ++k) {
      const long double a = static_cast<long double>(p.a_val[r][k]);
      ax += a * static_cast<long double>(ws.x[p.a_col[r][k]]);
      n2 += a * a;
    }
    const long double scale = n2 > 0.0L ? 1.0L / std::sqrt(n2) : 1.0L;
    const long double slack =
        std::fmin(static_cast<long double>(p.uba[r]) - ax, ax - static_cast<long double>(p.lba[r])) *
        scale;
    const long double cert = static_cast<long double>(ws.row_cert[r]);
    if (!std::isfinite(cert)) {
      // -inf: not yet evaluated in this solve; +inf: a row with no finite side.
      CHECK((cert < 0.0L || !std::isfinite(slack)));
      continue;
    }
    ++finite;
    const long double bound = cert - (prefix[end] - prefix[first]);
    if (!(slack >= bound - tol)) {
      FAIL_CHECK("row " << r << ": slack " << static_cast<double>(slack) << " < certified "
                        << static_cast<double>(bound));
    }
  }
  return finite;
}

// Stops the solve after k = 1, 2, ... iterations and checks the bookkeeping
// each time; finally the unrestricted solve.
template <class D, class Solve>
void check_every_iteration(Instance<D>& in, Solve solve) {
  in.settings.max_iterations = 0;
  REQUIRE(solve() == QpStatus::kOptimal);
  const int total = in.result.iterations;
  int checked_finite = check_certificates(in.problem, in.ws);
  for (int k = 1; k < total; ++k) {
    in.settings.max_iterations = k;
    const QpStatus st = solve();
    CHECK(st == QpStatus::kIterationLimit);
    checked_finite += check_certificates(in.problem, in.ws);
  }
  in.settings.max_iterations = 0;
  CHECK(checked_finite > 0);
}

template <class D>
void path_sequence() {
  auto in = std::make_unique<Instance<D>>();
  for (int k = 0; k < 3; ++k) {
    planner_qps::PathScenario sc;
    sc.init_l = 0.04 * k;
    sc.init_dl = 0.005 * k;
    sc.obstacle_left = 1.5 + 0.02 * k;
    REQUIRE(planner_qps::build_path_qp(in->problem, sc));
    sc.obstacle_s0 = 39.5;
    sc.obstacle_s1 = 54.5;
    REQUIRE(planner_qps::build_path_qp(in->next, sc));
    // cold
    check_every_iteration(*in, [&] {
      test_support::HeapGuard guard;
      return solve_cold(in->problem, in->ws, in->settings, in->result);
    });
    const WorkingSet<D> prev = in->result.working_set;
    // warm from the previous working set on the shifted obstacle
    std::swap(in->problem, in->next);
    check_every_iteration(*in, [&] {
      test_support::HeapGuard guard;
      return solve_warm(in->problem, in->ws, in->settings, prev, in->result);
    });
    // hot: same H and A, other bounds (back to the unshifted obstacle is a
    // bound change only in the corridor rows)
    std::swap(in->problem, in->next);
    check_every_iteration(*in, [&] {
      test_support::HeapGuard guard;
      // the workspace must hold the factor of this H and A: refresh it first
      // (uncapped, so that every hot solve starts from the same working set)
      QpResult<D> scratch;
      (void)solve_cold(in->next, in->ws, QpSettings<typename D::Scalar>{}, scratch);
      return solve_hot(in->problem, in->ws, in->settings, in->result);
    });
  }
}

}  // namespace

TEST_CASE("scan bookkeeping: row certificates bound the from-scratch slack, path QP, double") {
  path_sequence<PathQpDims<double, itp::DefaultConfig>>();
}

TEST_CASE("scan bookkeeping: row certificates bound the from-scratch slack, path QP, float") {
  path_sequence<PathQpDims<float, itp::DefaultConfig>>();
}

TEST_CASE("scan bookkeeping: random constructed QPs (scattered and clustered rows)") {
  using D = QpDims<double, 130, 260, 9, 6>;
  auto in = std::make_unique<Instance<D>>();
  std::mt19937 rng(7031);
  int solved = 0;
  for (int n : {5, 17, 40, 63, 130}) {
    for (int rep = 0; rep < 4; ++rep) {
      qp_test::BuildOptions o;
      o.n = n;
      o.m = 2 * n;
      o.bandwidth = 1 + rep % 6;
      o.max_row_nnz = 1 + (rep * 3) % 9;
      o.clustered_rows = rep % 2 == 0;
      (void)qp_test::build_random(in->problem, o, rng);
      in->settings.max_iterations = 0;
      if (solve_cold(in->problem, in->ws, in->settings, in->result) != QpStatus::kOptimal) continue;
      ++solved;
      check_every_iteration(*in, [&] {
        return solve_cold(in->problem, in->ws, in->settings, in->result);
      });
    }
  }
  CHECK(solved >= 15);
}

TEST_CASE("scan bookkeeping: the skipping scan selects what a full scan selects") {
  // Determinism across workspaces with different histories: a workspace that
  // solved other QPs first (stale certificates from another problem) gives
  // bit-identical results to a fresh one.
  using D = PathQpDims<double, itp::DefaultConfig>;
  auto a = std::make_unique<Instance<D>>();
  auto b = std::make_unique<Instance<D>>();
  planner_qps::PathScenario sc;
  REQUIRE(planner_qps::build_path_qp(a->problem, sc));
  sc.obstacle_left = 1.2;
  sc.init_l = 0.3;
  REQUIRE(planner_qps::build_path_qp(b->problem, sc));
  REQUIRE(solve_cold(b->problem, b->ws, b->settings, b->result) == QpStatus::kOptimal);
  REQUIRE(solve_cold(a->problem, b->ws, a->settings, b->result) == QpStatus::kOptimal);
  REQUIRE(solve_cold(a->problem, a->ws, a->settings, a->result) == QpStatus::kOptimal);
  CHECK(a->result.iterations == b->result.iterations);
  for (int j = 0; j < a->problem.n; ++j) CHECK(a->result.x[j] == b->result.x[j]);
  for (int r = 0; r < a->problem.m; ++r) CHECK(a->result.y_rows[r] == b->result.y_rows[r]);
}
