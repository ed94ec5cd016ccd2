// Rows of extreme norm and overflowing iterates (issue 13, defect 4): the old
// solver summed a_k^2 for the row norm, which overflowed for a row of 1e200,
// ranked every violation of the row as 0 and called x = 0 optimal although
// it violates the row; an iterate that overflowed to -inf was "optimal" too.
// These tests use only the solver's original API, so they also build (and
// fail) against the old solver.
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "heap_guard.hpp"
#include "qp_test_util.hpp"

using namespace itp::qp;

namespace {

using D8 = QpDims<double, 8, 16, 8, 7>;

}  // namespace

TEST_CASE("row scaling: a row of norm 1e200 or 1e-200 is enforced, not ignored") {
  auto in = std::make_unique<qp_test::Instance<D8>>();
  auto& p = in->problem;
  for (const double scale : {1e200, 1e-200, 1e150, 1.0}) {
    CAPTURE(scale);
    // min 1/2 |x|^2 s.t. scale (x0 + x1) >= scale: x = (1/2, 1/2), y = -1/(2 scale).
    REQUIRE(p.reset(2, 1));
    p.set_hessian(0, 0, 1.0);
    p.set_hessian(1, 1, 1.0);
    p.push_row_entry(0, 0, scale);
    p.push_row_entry(0, 1, scale);
    p.lba[0] = scale;
    REQUIRE(in->solve() == QpStatus::kOptimal);
    CHECK(in->result.x[0] == doctest::Approx(0.5).epsilon(1e-14));
    CHECK(in->result.x[1] == doctest::Approx(0.5).epsilon(1e-14));
    CHECK(in->result.y_rows[0] * scale == doctest::Approx(-0.5).epsilon(1e-14));
  }
}

TEST_CASE("row scaling: rows scaled from 1e-150 to 1e150 give the constructed optimum") {
  auto in = std::make_unique<qp_test::Instance<QpDims<double, 20, 30, 4, 2>>>();
  std::mt19937 rng(15);
  qp_test::BuildOptions o;
  o.n = 20;
  o.m = 30;
  o.bandwidth = 2;
  o.max_row_nnz = 4;
  o.p_row_active = 0.4;
  for (int rep = 0; rep < 10; ++rep) {
    auto c = qp_test::build_random(in->problem, o, rng);
    auto& p = in->problem;
    // Scale row r and its bounds by 2^k (exact), k spread over +-500: the
    // constructed x is unchanged, the multiplier scales by 2^-k.
    for (int r = 0; r < p.m; ++r) {
      const int k = -500 + (r * 1000) / (p.m - 1);
      const double f = std::ldexp(1.0, k);
      for (int q = 0; q < p.a_nnz[r]; ++q) p.a_val[r][q] *= f;
      p.lba[r] *= f;
      p.uba[r] *= f;
    }
    CAPTURE(rep);
    REQUIRE(in->solve() == QpStatus::kOptimal);
    CHECK(qp_test::max_abs_diff(in->result, c.x, p.n) < 1e-9 * (1.0 + qp_test::max_abs(c.x)));
  }
}

TEST_CASE("row scaling: an x that overflows is numerical trouble, never optimal") {
  auto in = std::make_unique<qp_test::Instance<D8>>();
  auto& p = in->problem;
  // x_unc = -H^-1 g = -1e300 / 1e-300 overflows to -inf.
  REQUIRE(p.reset(2, 1));
  p.set_hessian(0, 0, 1e-300);
  p.set_hessian(1, 1, 1.0);
  p.g[0] = 1e300;
  p.push_row_entry(0, 1, 1.0);
  p.lba[0] = 1.0;
  const QpStatus st = in->solve();
  CHECK_FALSE(in->result.usable());  // the old solver said optimal, x0 = -inf
  CHECK(std::string(to_string(st)) == "numerical_trouble");
}

