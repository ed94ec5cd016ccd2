// Statuses that can be trusted (issue 15 item 3): every kInfeasible comes
// with a dual ray that an independent long-double check accepts (Farkas:
// A'y = 0, support(y) < 0), also with rows scaled by 2^+-200.
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <random>

#include "heap_guard.hpp"
#include "qp_test_util.hpp"

using namespace itp::qp;

namespace {

template <class D>
struct Instance {
  QpProblem<D> problem;
  QpWorkspace<D> ws;
  QpResult<D> result;
  QpSettings<typename D::Scalar> settings;
  QpStatus solve() {
    test_support::HeapGuard guard;
    return solve_cold(problem, ws, settings, result);
  }
};

// Independent check of a Farkas ray in long double: returns |A'y + y_b|_inf
// and the support sum_{y>0} y ub + sum_{y<0} y lb, both relative to the
// largest |y_c| |a_c|.
template <class D>
void farkas(const QpProblem<D>& p, const QpResult<D>& r, long double& residual, long double& support) {
  long double ymax = 0;
  std::vector<long double> res(static_cast<std::size_t>(p.n), 0.0L);
  support = 0;
  for (int j = 0; j < p.n; ++j) {
    const long double y = r.y_bounds[j];
    ymax = std::max(ymax, std::abs(y));
    res[static_cast<std::size_t>(j)] += y;
    if (y != 0) support += y * (y > 0 ? p.ub[j] : p.lb[j]);
  }
  for (int i = 0; i < p.m; ++i) {
    const long double y = r.y_rows[i];
    if (y == 0) continue;
    long double n2 = 0;
    for (int k = 0; k < p.a_nnz[i]; ++k) {
      n2 += static_cast<long double>(p.a_val[i][k]) * p.a_val[i][k];
      res[static_cast<std::size_t>(p.a_col[i][k])] += y * p.a_val[i][k];
    }
    ymax = std::max(ymax, std::abs(y) * std::sqrt(n2));
    support += y * (y > 0 ? p.uba[i] : p.lba[i]);
  }
  residual = 0;
  for (long double v : res) residual = std::max(residual, std::abs(v));
  residual /= ymax;
  support /= ymax;
}

}  // namespace

TEST_CASE("trustworthy: every kInfeasible carries a dual ray that checks out") {
  // Random infeasible systems: k rows whose positive combination is 0 <= -c,
  // among harmless rows, with rows scaled by 2^+-200 and bounds as rows or
  // simple bounds. The ray reported must pass an independent check.
  auto in = std::make_unique<Instance<QpDims<double, 8, 16, 8, 2>>>();
  std::mt19937 rng(1315);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int infeasible = 0;
  for (int rep = 0; rep < 40; ++rep) {
    auto& p = in->problem;
    const int n = 3 + rep % 5;
    const int k = 2 + rep % 3;
    REQUIRE(p.reset(n, k + 2));
    for (int i = 0; i < n; ++i) {
      p.set_hessian(i, i, 1.0 + uni(rng));
      p.g[i] = gauss(rng);
    }
    std::vector<double> sum(static_cast<std::size_t>(n), 0.0);
    double yb = 0.0;
    for (int r = 0; r < k - 1; ++r) {
      const double y = 0.5 + uni(rng);
      for (int j = 0; j < n; ++j) {
        const double a = gauss(rng);
        p.push_row_entry(r, j, a);
        sum[static_cast<std::size_t>(j)] += y * a;
      }
      p.uba[r] = gauss(rng);
      yb += y * p.uba[r];
    }
    for (int j = 0; j < n; ++j) p.push_row_entry(k - 1, j, -sum[static_cast<std::size_t>(j)]);
    p.uba[k - 1] = -yb - 0.1 - uni(rng);
    for (int r = k; r < k + 2; ++r) {
      p.push_row_entry(r, r % n, 1.0);
      p.lba[r] = -10.0;
      p.uba[r] = 10.0;
    }
    // Exact power-of-two scaling of each row keeps the set unchanged.
    for (int r = 0; r < p.m; ++r) {
      const double f = std::ldexp(1.0, (r % 2 == 0 ? 200 : -200) * (rep % 3 == 0 ? 1 : 0));
      for (int q = 0; q < p.a_nnz[r]; ++q) p.a_val[r][q] *= f;
      p.lba[r] *= f;
      p.uba[r] *= f;
    }
    CAPTURE(rep);
    const QpStatus st = in->solve();
    CHECK(st == QpStatus::kInfeasible);
    if (st != QpStatus::kInfeasible) continue;
    ++infeasible;
    long double residual = 0, support = 0;
    farkas(p, in->result, residual, support);
    CHECK(residual < 1e-12L);
    CHECK(support < -1e-3L);
    // The solver's own figures describe the same ray.
    CHECK(static_cast<long double>(in->result.certificate_gap) == doctest::Approx(static_cast<double>(-support)).epsilon(1e-9));
    CHECK(in->result.certificate_residual < 1e-12);
  }
  CHECK(infeasible == 40);
}
