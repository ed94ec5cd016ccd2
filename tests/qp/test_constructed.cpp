// Random QPs whose optimum is known by construction (qp_test_util.hpp): the
// solver must find x* and a solution whose KKT residuals are small.
#include <doctest/doctest.h>

#include <cstring>
#include <memory>
#include <random>

#include "heap_guard.hpp"
#include "qp_test_util.hpp"

using namespace itp::qp;

namespace {

using BigD = QpDims<double, 130, 260, 9, 6>;
using BigF = QpDims<float, 130, 260, 9, 6>;
using SmallD = QpDims<double, 12, 30, 4, 3>;

template <class D>
struct Instance {
  QpProblem<D> problem;
  QpWorkspace<D> ws;
  QpResult<D> result;
};

// Solves under a heap guard and checks against the construction; true when
// the solve is optimal, x matches x* and the KKT residuals are small (so a
// caller's count of passing instances can fall short).
template <class D>
bool solve_and_check(Instance<D>& in, const qp_test::Constructed& c, double x_tol,
                     double kkt_tol) {
  QpSettings<typename D::Scalar> settings;
  QpStatus st;
  {
    test_support::HeapGuard guard;
    st = solve_cold(in.problem, in.ws, settings, in.result);
  }
  CHECK(st == QpStatus::kOptimal);
  if (st != QpStatus::kOptimal) {
    return false;
  }
  const double scale = 1.0 + qp_test::max_abs(c.x) + qp_test::max_abs(c.y_rows) +
                       qp_test::max_abs(c.y_bounds);
  const bool x_ok = qp_test::max_abs_diff(in.result, c.x, in.problem.n) <= x_tol * scale;
  CHECK(x_ok);
  const auto kkt = kkt_residual(in.problem, in.result);
  const bool kkt_ok = static_cast<double>(kkt.max()) <= kkt_tol * scale * scale;
  CHECK(kkt_ok);
  // A nonzero constructed multiplier means x* is not the unconstrained optimum.
  bool moved = true;
  if (qp_test::max_abs(c.y_rows) + qp_test::max_abs(c.y_bounds) > 0.0) {
    moved = in.result.iterations > 0;
    CHECK(moved);
  }
  return x_ok && kkt_ok && moved;
}

}  // namespace

TEST_CASE("constructed optimum: random banded QPs, n = 2..130, double") {
  auto in = std::make_unique<Instance<BigD>>();
  std::mt19937 rng(20240501);
  int solved = 0;
  for (int n : {2, 3, 5, 8, 13, 21, 34, 63, 90, 130}) {
    for (int rep = 0; rep < 6; ++rep) {
      qp_test::BuildOptions o;
      o.n = n;
      o.m = std::min(2 * n, 260);
      o.bandwidth = 1 + rep % 6;
      o.max_row_nnz = 1 + (rep * 3 + n) % 9;
      o.clustered_rows = rep % 2 == 0;
      o.p_row_active = 0.1 + 0.1 * (rep % 4);
      o.p_bound_active = 0.15;
      o.p_equality = rep == 5 ? 0.3 : 0.05;
      o.well_conditioned = rep != 3;
      CAPTURE(n);
      CAPTURE(rep);
      const auto c = qp_test::build_random(in->problem, o, rng);
      solved += solve_and_check(*in, c, 1e-6, 1e-7) ? 1 : 0;
    }
  }
  CHECK(solved == 60);
}

TEST_CASE("constructed optimum: float instantiation") {
  auto in = std::make_unique<Instance<BigF>>();
  std::mt19937 rng(99);
  for (int n : {2, 4, 9, 20, 40, 63}) {
    for (int rep = 0; rep < 4; ++rep) {
      qp_test::BuildOptions o;
      o.n = n;
      o.m = 2 * n;
      o.bandwidth = 1 + rep % 5;
      o.max_row_nnz = 2 + rep % 6;
      o.p_row_active = 0.2;
      o.p_bound_active = 0.1;
      CAPTURE(n);
      CAPTURE(rep);
      const auto c = qp_test::build_random(in->problem, o, rng);
      solve_and_check(*in, c, 2e-3, 2e-3);
    }
  }
}

TEST_CASE("constructed optimum: weakly active constraints (zero multipliers, ties)") {
  auto in = std::make_unique<Instance<BigD>>();
  std::mt19937 rng(5);
  for (int n : {4, 10, 30, 63}) {
    for (int rep = 0; rep < 4; ++rep) {
      qp_test::BuildOptions o;
      o.n = n;
      o.m = 2 * n;
      o.bandwidth = 3;
      o.max_row_nnz = 4;
      o.p_row_active = 0.4;
      o.p_bound_active = 0.3;
      o.p_weak = 0.5;
      CAPTURE(n);
      CAPTURE(rep);
      const auto c = qp_test::build_random(in->problem, o, rng);
      solve_and_check(*in, c, 1e-6, 1e-7);
    }
  }
}

TEST_CASE("constructed optimum: duplicate and redundant active rows") {
  auto in = std::make_unique<Instance<SmallD>>();
  std::mt19937 rng(17);
  for (int rep = 0; rep < 20; ++rep) {
    qp_test::BuildOptions o;
    o.n = 10;
    o.m = 20;
    o.bandwidth = 3;
    o.max_row_nnz = 2;
    o.p_row_active = 0.5;
    o.p_bound_active = 0.1;
    o.p_equality = 0.0;
    auto c = qp_test::build_random(in->problem, o, rng);
    auto& p = in->problem;
    // Rows 20..29: copies of active rows (same side and bound) and sums of
    // pairs of rows active at their upper side (redundant, multiplier 0).
    p.m = 30;
    int first_upper = -1;
    for (int r = 20; r < 30; ++r) {
      p.a_nnz[r] = 0;
      c.y_rows.push_back(0.0);
    }
    int r = 20;
    for (int src = 0; src < 20 && r < 25; ++src) {
      if (c.y_rows[static_cast<std::size_t>(src)] == 0.0) continue;
      for (int k = 0; k < p.a_nnz[src]; ++k) REQUIRE(p.push_row_entry(r, p.a_col[src][k], p.a_val[src][k]));
      p.lba[r] = p.lba[src];
      p.uba[r] = p.uba[src];
      // split the multiplier between the two copies
      c.y_rows[static_cast<std::size_t>(r)] = 0.5 * c.y_rows[static_cast<std::size_t>(src)];
      c.y_rows[static_cast<std::size_t>(src)] *= 0.5;
      ++r;
    }
    for (int src = 0; src < 20 && r < 30; ++src) {
      if (!(c.y_rows[static_cast<std::size_t>(src)] > 0.0)) continue;
      if (first_upper < 0) {
        first_upper = src;
        continue;
      }
      // row = a_first + a_src (columns merged), active at upper side.
      double dense[10] = {};
      for (int k = 0; k < p.a_nnz[first_upper]; ++k) dense[p.a_col[first_upper][k]] += p.a_val[first_upper][k];
      for (int k = 0; k < p.a_nnz[src]; ++k) dense[p.a_col[src][k]] += p.a_val[src][k];
      int nnz = 0;
      for (double v : dense) nnz += v != 0.0 ? 1 : 0;
      if (nnz > 4) continue;
      double val = 0.0;
      for (int j = 0; j < 10; ++j) {
        if (dense[j] != 0.0) {
          REQUIRE(p.push_row_entry(r, j, dense[j]));
          val += dense[j] * c.x[static_cast<std::size_t>(j)];
        }
      }
      p.uba[r] = val;
      p.lba[r] = val - 1.0;
      ++r;
    }
    p.m = r;
    c.y_rows.resize(static_cast<std::size_t>(r));
    qp_test::finish_gradient(p, c);
    CAPTURE(rep);
    solve_and_check(*in, c, 1e-7, 1e-8);
  }
}

TEST_CASE("same input gives bit-identical output") {
  auto a = std::make_unique<Instance<BigD>>();
  auto b = std::make_unique<Instance<BigD>>();
  std::mt19937 rng(3);
  qp_test::BuildOptions o;
  o.n = 63;
  o.m = 120;
  o.bandwidth = 5;
  o.max_row_nnz = 6;
  o.p_row_active = 0.3;
  qp_test::build_random(a->problem, o, rng);
  b->problem = a->problem;
  QpSettings<double> s;
  // b's workspace has seen another problem first.
  qp_test::BuildOptions o2 = o;
  o2.n = 20;
  auto other = std::make_unique<Instance<BigD>>();
  qp_test::build_random(other->problem, o2, rng);
  solve_cold(other->problem, b->ws, s, b->result);
  REQUIRE(solve_cold(a->problem, a->ws, s, a->result) == QpStatus::kOptimal);
  REQUIRE(solve_cold(b->problem, b->ws, s, b->result) == QpStatus::kOptimal);
  CHECK(std::memcmp(a->result.x, b->result.x, sizeof(double) * 63) == 0);
  CHECK(std::memcmp(a->result.y_rows, b->result.y_rows, sizeof(double) * 120) == 0);
  CHECK(a->result.iterations == b->result.iterations);
  CHECK(std::memcmp(&a->result.objective, &b->result.objective, sizeof(double)) == 0);
}
