// qp-text/1 reader/writer: round trip through the solver's sparse form,
// rejection of malformed files and of an H wider than the band capacity.
#include <doctest/doctest.h>

#include <memory>
#include <sstream>

#include "formats/qp_text.hpp"
#include "heap_guard.hpp"
#include "planner_qps.hpp"

using namespace itp::qp;
using hil::formats::QpText;

TEST_CASE("qp-text/1 round trip of the path QP is exact") {
  auto p = std::make_unique<QpProblem<PathQpDims<double, itp::DefaultConfig>>>();
  auto q = std::make_unique<QpProblem<PathQpDims<double, itp::DefaultConfig>>>();
  REQUIRE(planner_qps::build_path_qp(*p, planner_qps::PathScenario{}));
  QpText text = hil::formats::from_problem(*p);
  text.obj_ref = 1.25;
  std::stringstream ss;
  hil::formats::write_qp_text(ss, text);
  QpText back;
  std::string error;
  REQUIRE(hil::formats::read_qp_text(ss, back, error));
  REQUIRE(hil::formats::to_problem(back, *q, error));
  CHECK(back.obj_ref.value() == 1.25);
  CHECK(q->n == p->n);
  CHECK(q->m == p->m);
  for (int i = 0; i < p->n; ++i) {
    for (int j = 0; j < p->n; ++j) CHECK(q->hessian(i, j) == p->hessian(i, j));
    CHECK(q->g[i] == p->g[i]);
    CHECK(q->lb[i] == p->lb[i]);
    CHECK(q->ub[i] == p->ub[i]);
  }
  for (int r = 0; r < p->m; ++r) {
    // explicit zeros of the sparse form are dropped by the dense file
    double dp[63] = {}, dq[63] = {};
    for (int k = 0; k < p->a_nnz[r]; ++k) dp[p->a_col[r][k]] = p->a_val[r][k];
    for (int k = 0; k < q->a_nnz[r]; ++k) {
      CHECK(q->a_val[r][k] != 0.0);
      dq[q->a_col[r][k]] = q->a_val[r][k];
    }
    for (int j = 0; j < 63; ++j) CHECK(dq[j] == dp[j]);
    CHECK(q->lba[r] == p->lba[r]);
    CHECK(q->uba[r] == p->uba[r]);
  }
}

TEST_CASE("qp-text/1: errors are reported, not guessed around") {
  QpText qp;
  std::string error;
  auto parse = [&](const std::string& s) {
    std::stringstream ss(s);
    return hil::formats::read_qp_text(ss, qp, error);
  };
  CHECK_FALSE(parse("qp-text/2\nn 1 m 0\n"));
  CHECK_FALSE(parse("qp-text/1\nn 2 m 0\nH\n1 0 0\n"));  // H ends early
  CHECK(error.find("H") != std::string::npos);
  CHECK_FALSE(parse("qp-text/1\nn 1 m 0\nH\n1\ng\nabc\nA\nlbA\nubA\nlb\n0\nub\n1\n"));
  CHECK(parse("qp-text/1\n# comment\nn 1 m 0\nH\n1\ng\n2 # trailing comment\nA\nlbA\nubA\nlb\n-inf\nub\ninf\n"));
  CHECK(qp.g[0] == 2.0);
  // H with half-bandwidth 3 does not fit a capacity of 2.
  CHECK(parse("qp-text/1\nn 4 m 0\nH\n1 0 0 0.5\n0 1 0 0\n0 0 1 0\n0.5 0 0 1\ng\n0 0 0 0\nA\nlbA\nubA\n"
              "lb\n-inf -inf -inf -inf\nub\ninf inf inf inf\n"));
  auto p = std::make_unique<QpProblem<QpDims<double, 8, 4, 2, 2>>>();
  CHECK_FALSE(hil::formats::to_problem(qp, *p, error));
  CHECK(error.find("not banded") != std::string::npos);
  // not symmetric
  qp.H[3] = 0.25;
  CHECK_FALSE(hil::formats::to_problem(qp, *p, error));
  CHECK(error.find("symmetric") != std::string::npos);
}

TEST_CASE("qp-text/1: the header cannot make the reader allocate (issue 13, defect 5)") {
  QpText qp;
  std::string error;
  auto parse = [&](const std::string& s) {
    std::stringstream ss(s);
    return hil::formats::read_qp_text(ss, qp, error);
  };
  for (const std::string tiny : {"qp-text/1\nn 20000 m 0\nH\n0\n", "qp-text/1\nn 9999 m 99999\nH"}) {
    // Files of 26 bytes that made the old reader ask for 3.2 GB and 0.8 GB
    // (aborting qp_solve with std::bad_alloc where that failed): refused on
    // the header, nothing allocated for data.
    CAPTURE(tiny);
    REQUIRE(tiny.size() == 26);
    test_support::HeapGuard guard(test_support::HeapGuard::Mode::kObserveOnly);
    CHECK_FALSE(parse(tiny));
    CHECK(guard.bytes() < 64 * 1024);
    CHECK(error.find("limits") != std::string::npos);
  }
  {
    // Within the limits, but the file ends early: memory follows the data
    // actually read (the old reader allocated n(n + m) doubles, 2 GB here).
    test_support::HeapGuard guard(test_support::HeapGuard::Mode::kObserveOnly);
    CHECK_FALSE(parse("qp-text/1\nn 4096 m 4096\nH\n1 0 0\n"));
    CHECK(guard.bytes() < 1024 * 1024);
  }
  CHECK(error.find("file ended") != std::string::npos);
  CHECK_FALSE(parse("qp-text/1\nn 4097 m 0\n"));
  CHECK_FALSE(parse("qp-text/1\nn 1 m 70000\n"));
  CHECK_FALSE(parse("qp-text/1\nn 1e300 m 0\n"));
  CHECK_FALSE(parse("qp-text/1\nn -1 m 0\n"));
  CHECK_FALSE(parse("qp-text/1\nn 2.5 m 0\n"));
}
