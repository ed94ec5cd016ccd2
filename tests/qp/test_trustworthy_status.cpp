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
  // Random infeasible systems (qp_test::build_farkas) with, in every third,
  // rows scaled by 2^+-200. The ray reported must pass an independent check.
  auto in = std::make_unique<qp_test::Instance<QpDims<double, 8, 16, 8, 2>>>();
  std::mt19937 rng(1315);
  int infeasible = 0;
  for (int rep = 0; rep < 40; ++rep) {
    auto& p = in->problem;
    qp_test::build_farkas(p, 3 + rep % 5, 2 + rep % 3, rep % 2 == 1, rng);
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
