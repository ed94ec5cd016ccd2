// Infeasibility, equality-constrained QPs against an independent dense KKT
// solve, invalid input, non-convexity and the iteration limit.
#undef EIGEN_NO_MALLOC  // the dense reference allocates; never inside a guard
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <memory>
#include <random>

#include "heap_guard.hpp"
#include "qp_test_util.hpp"

using namespace itp::qp;

namespace {

using D8 = QpDims<double, 8, 16, 8, 7>;
using D40 = QpDims<double, 40, 80, 6, 4>;

template <class D>
void identity_hessian(QpProblem<D>& p) {
  for (int i = 0; i < p.n; ++i) p.set_hessian(i, i, 1.0);
}

// One row of C x = d: its nonzeros (column, value) and d.
using EqualityRow = std::pair<std::vector<std::pair<int, double>>, double>;

// Row r of p's A with the right-hand side d.
template <class D>
EqualityRow equality_row(const QpProblem<D>& p, int r, double d) {
  std::vector<std::pair<int, double>> a;
  for (int k = 0; k < p.a_nnz[r]; ++k) a.push_back({p.a_col[r][k], p.a_val[r][k]});
  return {a, d};
}

// The independent reference: the dense KKT system [H C'; C 0] [x; y] = [-g; d]
// of p's H and g with the rows `eq`, solved by full-pivoting LU (x, then one y
// per row); the solve must hold to 1e-9.
template <class D>
Eigen::VectorXd dense_kkt_solve(const QpProblem<D>& p, const std::vector<EqualityRow>& eq) {
  const int n = p.n;
  const int m = static_cast<int>(eq.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n + m, n + m);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + m);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) K(i, j) = p.hessian(i, j);
    rhs(i) = -p.g[i];
  }
  int e = 0;
  for (const auto& [a, d] : eq) {
    for (const auto& [j, v] : a) K(n + e, j) = K(j, n + e) = v;
    rhs(n + e) = d;
    ++e;
  }
  const Eigen::VectorXd ref = K.fullPivLu().solve(rhs);
  REQUIRE((K * ref - rhs).norm() < 1e-9 * (1.0 + rhs.norm()));
  return ref;
}

}  // namespace

TEST_CASE("infeasible: contradictory rows and bounds are detected") {
  auto in = std::make_unique<qp_test::Instance<D8>>();
  auto& p = in->problem;
  SUBCASE("a'x >= 1 and a'x <= 0") {
    REQUIRE(p.reset(3, 2));
    identity_hessian(p);
    for (int r = 0; r < 2; ++r) {
      p.push_row_entry(r, 0, 1.0);
      p.push_row_entry(r, 2, -2.0);
    }
    p.lba[0] = 1.0;
    p.uba[1] = 0.0;
    CHECK(in->solve() == QpStatus::kInfeasible);
  }
  SUBCASE("x0 + x1 >= 3 with x <= 1") {
    REQUIRE(p.reset(2, 1));
    identity_hessian(p);
    p.push_row_entry(0, 0, 1.0);
    p.push_row_entry(0, 1, 1.0);
    p.lba[0] = 3.0;
    p.ub[0] = p.ub[1] = 1.0;
    CHECK(in->solve() == QpStatus::kInfeasible);
  }
  SUBCASE("zero row with a positive lower bound") {
    REQUIRE(p.reset(2, 1));
    identity_hessian(p);
    p.lba[0] = 0.5;
    CHECK(in->solve() == QpStatus::kInfeasible);
  }
  SUBCASE("inconsistent equalities") {
    REQUIRE(p.reset(3, 2));
    identity_hessian(p);
    p.push_row_entry(0, 0, 1.0);
    p.push_row_entry(0, 1, 1.0);
    p.push_row_entry(1, 0, 2.0);
    p.push_row_entry(1, 1, 2.0);
    p.lba[0] = p.uba[0] = 1.0;
    p.lba[1] = p.uba[1] = 3.0;
    CHECK(in->solve() == QpStatus::kInfeasible);
  }
}

TEST_CASE("infeasible: random Farkas certificates") {
  // Rows a_1..a_k with y >= 0, sum y_i a_i = 0 and sum y_i b_i < 0 make
  // {a_i'x <= b_i} empty. The other rows are random and harmless.
  auto in = std::make_unique<qp_test::Instance<D8>>();
  std::mt19937 rng(77);
  for (int rep = 0; rep < 30; ++rep) {
    const int n = 2 + rep % 7;
    const int k = 2 + rep % 4;
    qp_test::build_farkas(in->problem, n, k, rep % 2 == 1, rng);
    CAPTURE(rep);
    CHECK(in->solve() == QpStatus::kInfeasible);
  }
}

TEST_CASE("equality-constrained QPs match a dense KKT solve") {
  auto in = std::make_unique<qp_test::Instance<D40>>();
  std::mt19937 rng(4242);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (int rep = 0; rep < 12; ++rep) {
    const int n = 6 + 3 * rep;
    const int m = n / 3 + rep % 3;
    qp_test::BuildOptions o;
    o.n = std::min(n, 40);
    o.m = 0;
    o.bandwidth = 4;
    auto& p = in->problem;
    qp_test::build_random(p, o, rng);
    p.m = m;
    for (int r = 0; r < m; ++r) {
      p.a_nnz[r] = 0;
      // each row touches a diagonal-ish window so the rows are independent
      const int c0 = (r * (o.n - 3)) / std::max(1, m - 1);
      for (int j = c0; j < std::min(o.n, c0 + 3); ++j) p.push_row_entry(r, j, gauss(rng));
      p.lba[r] = p.uba[r] = gauss(rng);
    }
    for (int i = 0; i < o.n; ++i) {
      p.g[i] = gauss(rng);
      p.lb[i] = -qp_test::inf<double>();
      p.ub[i] = qp_test::inf<double>();
    }
    // Dense KKT: [H A'; A 0] [x; y] = [-g; b]
    const int nn = o.n;
    std::vector<EqualityRow> eq;
    for (int r = 0; r < m; ++r) eq.push_back(equality_row(p, r, p.lba[r]));
    const Eigen::VectorXd ref = dense_kkt_solve(p, eq);
    CAPTURE(rep);
    REQUIRE(in->solve() == QpStatus::kOptimal);
    for (int i = 0; i < nn; ++i) CHECK(in->result.x[i] == doctest::Approx(ref(i)).epsilon(1e-8));
    for (int r = 0; r < m; ++r) CHECK(in->result.y_rows[r] == doctest::Approx(ref(nn + r)).epsilon(1e-7));
    // Every equality is in the final working set.
    CHECK(in->result.working_set.size == m);
  }
}

TEST_CASE("bad inputs are rejected with kInvalidInput") {
  auto in = std::make_unique<qp_test::Instance<D8>>();
  auto& p = in->problem;
  auto base = [&]() {
    REQUIRE(p.reset(3, 2));
    identity_hessian(p);
    p.push_row_entry(0, 0, 1.0);
    p.push_row_entry(0, 1, 1.0);
    p.push_row_entry(1, 2, 1.0);
    p.lba[0] = 0.0;
    p.uba[0] = 1.0;
  };
  base();
  REQUIRE(in->solve() == QpStatus::kOptimal);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = qp_test::inf<double>();
  SUBCASE("NaN in g") { base(); p.g[1] = nan; }
  SUBCASE("Inf in H") { base(); p.h_band[2][0] = inf; }
  SUBCASE("NaN in A") { base(); p.a_val[0][1] = nan; }
  SUBCASE("Inf in A") { base(); p.a_val[1][0] = -inf; }
  // A first value whose square overflows: the row's sum of squares no longer
  // proves the rest finite (rows_valid tests such a row value by value).
  SUBCASE("NaN behind a value whose square overflows") { base(); p.a_val[0][0] = 1e200; p.a_val[0][1] = nan; }
  SUBCASE("Inf behind a value whose square overflows") { base(); p.a_val[0][0] = 1e200; p.a_val[0][1] = inf; }
  SUBCASE("lb > ub") { base(); p.lb[0] = 1.0; p.ub[0] = 0.0; }
  SUBCASE("lbA > ubA") { base(); p.lba[1] = 2.0; p.uba[1] = 1.0; }
  SUBCASE("lb = +inf") { base(); p.lb[2] = inf; }
  SUBCASE("NaN bound") { base(); p.ub[1] = nan; }
  SUBCASE("n beyond capacity") { base(); p.n = 9; }
  SUBCASE("n = 0") { base(); p.n = 0; }
  SUBCASE("m beyond capacity") { base(); p.m = 17; }
  SUBCASE("column out of range") { base(); p.a_col[1][0] = 3; }
  SUBCASE("columns not increasing") { base(); p.a_col[0][1] = 0; }
  SUBCASE("nnz beyond capacity") { base(); p.a_nnz[0] = 9; }
  CHECK(in->solve() == QpStatus::kInvalidInput);
  CHECK_FALSE(in->result.usable());
  CHECK_FALSE(p.reset(9, 1));
  CHECK_FALSE(p.reset(2, 17));
}

TEST_CASE("a row of finite values whose sum of squares overflows is valid input") {
  auto in = std::make_unique<qp_test::Instance<D8>>();
  auto& p = in->problem;
  REQUIRE(p.reset(3, 1));
  identity_hessian(p);
  p.push_row_entry(0, 0, 1e200);
  p.push_row_entry(0, 2, -1e200);
  p.lba[0] = -1.0;
  p.uba[0] = 1.0;
  CHECK(is_valid(p));
  CHECK(in->solve() != QpStatus::kInvalidInput);
}

TEST_CASE("a semidefinite H is solved exactly, kNotConvex needs a negative eigenvalue") {
  auto in = std::make_unique<qp_test::Instance<D8>>();
  auto& p = in->problem;
  REQUIRE(p.reset(3, 0));
  // H = [[1,1,0],[1,1,0],[0,0,1]] is semidefinite (null vector (1,-1,0)).
  // min 1/2 (x0 + x1)^2 + 1/2 x2^2 + x0 on |x0|, |x1| <= 1: the objective is
  // >= x0 >= -1, reached only at x = (-1, 1, 0) (x0 + x1 = 0), so -1 there.
  p.set_hessian(0, 0, 1.0);
  p.set_hessian(1, 0, 1.0);
  p.set_hessian(1, 1, 1.0);
  p.set_hessian(2, 2, 1.0);
  p.lb[0] = p.lb[1] = -1.0;
  p.ub[0] = p.ub[1] = 1.0;
  p.g[0] = 1.0;
  REQUIRE(in->solve() == QpStatus::kOptimal);
  CHECK(in->result.proximal_steps > 0);
  CHECK(in->result.x[0] == doctest::Approx(-1.0).epsilon(1e-12));
  CHECK(in->result.x[1] == doctest::Approx(1.0).epsilon(1e-9));
  CHECK(std::abs(in->result.x[2]) < 1e-9);
  CHECK(in->result.objective == doctest::Approx(-1.0).epsilon(1e-12));
  CHECK(kkt_residual(p, in->result).max() < 1e-8);
  // A user-chosen proximal weight gives the same optimum, not a perturbed one.
  in->settings.proximal_weight = 1e-2;
  REQUIRE(in->solve() == QpStatus::kOptimal);
  CHECK(in->result.x[1] == doctest::Approx(1.0).epsilon(1e-9));
  in->settings.proximal_weight = 0.0;
  p.set_hessian(1, 1, -2.0);  // indefinite: v = (1, -1, 0) gives v'Hv = -1
  CHECK(in->solve() == QpStatus::kNotConvex);
  // hotstart is refused after a failed factorisation
  QpResult<D8> r;
  CHECK(solve_hot(p, in->ws, in->settings, r) == QpStatus::kNotFactored);
  // A negative eigenvalue below the proximal weight is still found (the
  // shifted factor fails too, and its witness is checked against H itself).
  p.set_hessian(1, 1, 1.0 - 1e-9);  // eigenvalues of the block: ~2, ~-5e-10
  CHECK(in->solve() == QpStatus::kNotConvex);
  // H = diag(0, -1e-9): the first pivot fails only by being zero, H + eps I is
  // positive definite, and the proximal steps find d'Hd < 0 along x1.
  REQUIRE(p.reset(2, 0));
  p.set_hessian(1, 1, -1e-9);
  p.g[0] = 1.0;
  p.g[1] = 1e-3;
  p.lb[0] = p.lb[1] = -1.0;
  p.ub[0] = p.ub[1] = 1.0;
  CHECK(in->solve() == QpStatus::kNotConvex);
}

TEST_CASE("a convex QP unbounded below is kUnbounded, a bounded LP is solved") {
  auto in = std::make_unique<qp_test::Instance<D8>>();
  auto& p = in->problem;
  // min 1/2 x0^2 - x1 s.t. x0 + x1 <= 1, x1 >= -5: x1 = 1 - x0 -> 1/2 x0^2 + x0 - 1,
  // optimum x0 = -1, x1 = 2, objective -1.5 (x1 only has a linear cost).
  REQUIRE(p.reset(2, 1));
  p.set_hessian(0, 0, 1.0);
  p.g[1] = -1.0;
  p.push_row_entry(0, 0, 1.0);
  p.push_row_entry(0, 1, 1.0);
  p.uba[0] = 1.0;
  p.lb[1] = -5.0;
  REQUIRE(in->solve() == QpStatus::kOptimal);
  CHECK(in->result.x[0] == doctest::Approx(-1.0).epsilon(1e-9));
  CHECK(in->result.x[1] == doctest::Approx(2.0).epsilon(1e-9));
  CHECK(in->result.objective == doctest::Approx(-1.5).epsilon(1e-9));
  // Without the row, x1 runs to +inf: unbounded, never "optimal" or a limit.
  p.m = 0;
  CHECK(in->solve() == QpStatus::kUnbounded);
  CHECK_FALSE(in->result.usable());
}

TEST_CASE("the iteration limit is honoured and flags the iterate unusable") {
  auto in = std::make_unique<qp_test::Instance<D40>>();
  std::mt19937 rng(8);
  qp_test::BuildOptions o;
  o.n = 40;
  o.m = 80;
  o.bandwidth = 4;
  o.max_row_nnz = 5;
  o.p_row_active = 0.4;
  qp_test::build_random(in->problem, o, rng);
  REQUIRE(in->solve() == QpStatus::kOptimal);
  const int needed = in->result.iterations;
  REQUIRE(needed > 3);
  in->settings.max_iterations = needed - 1;
  CHECK(in->solve() == QpStatus::kIterationLimit);
  CHECK(in->result.iterations == needed - 1);
  CHECK_FALSE(in->result.usable());
  in->settings.max_iterations = needed;
  CHECK(in->solve() == QpStatus::kOptimal);
  static_assert(D40::kMaxIterations == 3 * (40 + 80));
}

// The cold start puts the equalities that x_unc violates into W before the
// first scan (solver.hpp, load_equalities). Fixed variables, equality rows, a
// consistent duplicate of a row and a row that repeats a fixed variable (both
// dependent: left to the loop) against a dense KKT solve of the independent
// ones; with max_iterations below the count of violated equalities the
// preload stops at the cap. The dependent rows come second and third, so
// that one left in W would sit inside the factor, not last.
TEST_CASE("equality preload: fixed variables, equality rows and dependent duplicates match a dense KKT solve") {
  auto in = std::make_unique<qp_test::Instance<D40>>();
  std::mt19937 rng(515);
  std::normal_distribution<double> gauss(0.0, 1.0);
  int with_inequalities = 0;  // members whose optimum holds an inequality too
  for (int rep = 0; rep < 20; ++rep) {
    CAPTURE(rep);
    const int n = 8 + rep;
    const int fixed = 1 + rep % 3;  // x_0 .. x_{fixed-1}
    const int rows = 2 + rep % 4;   // independent equality rows: 0 and 3 .. rows + 1
    auto& p = in->problem;
    REQUIRE(p.reset(n, rows + 2 + 3));
    for (int i = 0; i < n; ++i) {
      p.set_hessian(i, i, 4.0 + gauss(rng) * 0.1);
      if (i > 0) p.set_hessian(i, i - 1, 1.0);
      p.g[i] = 10.0 * gauss(rng);
    }
    Eigen::VectorXd fixed_value(fixed);
    for (int i = 0; i < fixed; ++i) p.lb[i] = p.ub[i] = fixed_value(i) = gauss(rng);
    std::vector<int> independent;
    for (int q = 0; q < rows; ++q) {
      const int r = q == 0 ? 0 : q + 2;
      independent.push_back(r);
      const int c0 = fixed + (q * (n - fixed - 3)) / std::max(1, rows - 1);
      for (int j = c0; j < c0 + 3; ++j) p.push_row_entry(r, j, 1.0 + gauss(rng) * 0.3);
      p.lba[r] = p.uba[r] = gauss(rng);
    }
    // Row 1: 2 x (row 0), consistent; row 2: 3 x_0 = 3 b_0.
    for (int k = 0; k < p.a_nnz[0]; ++k) p.push_row_entry(1, p.a_col[0][k], 2.0 * p.a_val[0][k]);
    p.lba[1] = p.uba[1] = 2.0 * p.lba[0];
    p.push_row_entry(2, 0, 3.0);
    p.lba[2] = p.uba[2] = 3.0 * fixed_value(0);
    // Three inequality rows on the last variables, a bound too.
    for (int q = 0; q < 3; ++q) {
      p.push_row_entry(rows + 2 + q, n - 1 - q, 1.0);
      p.uba[rows + 2 + q] = 0.5 + q;
    }
    p.ub[n - 4] = -0.25;
    // Reference: the dense KKT solve of the independent equalities and of
    // every other constraint the solver reports active (its final working
    // set); a wrong active set fails the multiplier signs below, a wrong
    // value the match.
    REQUIRE(in->solve() == QpStatus::kOptimal);
    const auto& ws = in->result.working_set;
    std::vector<EqualityRow> eq;
    for (int i = 0; i < fixed; ++i) eq.push_back({{{i, 1.0}}, fixed_value(i)});
    for (const int r : independent) eq.push_back(equality_row(p, r, p.lba[r]));
    for (int e = 0; e < ws.size; ++e) {
      const auto& c = ws.entries[e];
      if (c.is_bound && c.index < fixed) continue;
      if (!c.is_bound && c.index < rows + 2) continue;
      if (c.is_bound) {
        eq.push_back({{{c.index, 1.0}}, c.side > 0 ? p.ub[c.index] : p.lb[c.index]});
      } else {
        eq.push_back(equality_row(p, c.index, c.side > 0 ? p.uba[c.index] : p.lba[c.index]));
      }
    }
    with_inequalities += static_cast<int>(eq.size()) > fixed + rows ? 1 : 0;
    const Eigen::VectorXd ref = dense_kkt_solve(p, eq);
    for (int i = 0; i < n; ++i) CHECK(in->result.x[i] == doctest::Approx(ref(i)).epsilon(1e-8));
    // The dependent duplicates hold at the optimum.
    double a0x = 0.0;
    for (int k = 0; k < p.a_nnz[0]; ++k) a0x += p.a_val[0][k] * in->result.x[p.a_col[0][k]];
    CHECK(a0x == doctest::Approx(p.lba[0]).epsilon(1e-9));
    CHECK(in->result.x[0] == doctest::Approx(fixed_value(0)).epsilon(1e-12));
    // The rest of KKT for the inequalities: feasible, and multipliers of the
    // right sign (QpResult: y > 0 on an active upper side).
    for (int q = 0; q < 3; ++q) {
      CHECK(in->result.x[n - 1 - q] <= p.uba[rows + 2 + q] + 1e-9);
      CHECK(in->result.y_rows[rows + 2 + q] >= -1e-9);
    }
    CHECK(in->result.x[n - 4] <= p.ub[n - 4] + 1e-9);
    CHECK(in->result.y_bounds[n - 4] >= -1e-9);
    // The cap: fewer iterations than violated equalities stops in the preload.
    const int needed = in->result.iterations;
    REQUIRE(needed >= 2);
    in->settings.max_iterations = 1;
    CHECK(in->solve() == QpStatus::kIterationLimit);
    CHECK(in->result.iterations == 1);
    in->settings.max_iterations = needed;
    CHECK(in->solve() == QpStatus::kOptimal);
    in->settings.max_iterations = 0;
  }
  MESSAGE("equality preload: " << with_inequalities << " of 20 optima hold an inequality");
  CHECK(with_inequalities >= 5);
}
