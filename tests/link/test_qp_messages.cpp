#include <doctest/doctest.h>

#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "itp/link/qp_messages.hpp"

using D = itp::qp::PathQpDims<double, itp::DefaultConfig>;

TEST_CASE("a QpSolve request round-trips every number, infinities included") {
  auto a = std::make_unique<itp::qp::QpProblem<D>>();
  auto b = std::make_unique<itp::qp::QpProblem<D>>();
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-2, 2);
  REQUIRE(a->reset(63, 300));
  for (int i = 0; i < 63; ++i) {
    for (int k = 0; k <= 5 && k <= i; ++k) a->h_band[i][k] = u(rng);
    a->g[i] = u(rng);
    a->lb[i] = i % 3 == 0 ? -std::numeric_limits<double>::infinity() : -1;
    a->ub[i] = 1;
  }
  for (int r = 0; r < 300; ++r) {
    for (int k = 0; k < 6; ++k) REQUIRE(a->push_row_entry(r, (r % 57) + k, u(rng)));
    a->lba[r] = -u(rng) - 3;
    a->uba[r] = r % 2 ? std::numeric_limits<double>::infinity() : 5;
  }
  std::vector<std::uint8_t> body(itp::link::kMaxQpRequestBytes<D>);
  const std::size_t n = itp::link::encode_qp_request(*a, body);
  REQUIRE(n > 0);
  REQUIRE(n <= itp::link::kMaxQpRequestBytes<D>);
  REQUIRE(itp::link::decode_qp_request(std::span<const std::uint8_t>(body.data(), n), *b));
  CHECK(b->n == 63);
  CHECK(b->m == 300);
  for (int i = 0; i < 63; ++i) {
    for (int k = 0; k <= 5 && k <= i; ++k) CHECK(b->h_band[i][k] == a->h_band[i][k]);
    CHECK(b->g[i] == a->g[i]);
    CHECK(b->lb[i] == a->lb[i]);
    CHECK(b->ub[i] == a->ub[i]);
  }
  for (int r = 0; r < 300; ++r) {
    REQUIRE(b->a_nnz[r] == a->a_nnz[r]);
    for (int k = 0; k < a->a_nnz[r]; ++k) {
      CHECK(b->a_col[r][k] == a->a_col[r][k]);
      CHECK(b->a_val[r][k] == a->a_val[r][k]);
    }
    CHECK(b->lba[r] == a->lba[r]);
    CHECK(b->uba[r] == a->uba[r]);
  }
  // Truncated bodies are rejected.
  CHECK_FALSE(itp::link::decode_qp_request(std::span<const std::uint8_t>(body.data(), n - 1), *b));
  CHECK_FALSE(itp::link::decode_qp_request(std::span<const std::uint8_t>(body.data(), 3), *b));
}

TEST_CASE("a QpSolve reply round-trips") {
  itp::link::QpSolveReply<D> r;
  r.status = itp::qp::QpStatus::kInfeasible;
  r.iterations = 17;
  r.n = 5;
  r.objective = -3.25;
  r.ticks = 123456789;
  for (int i = 0; i < 5; ++i) r.x[i] = 0.5 * i;
  std::vector<std::uint8_t> body(1024);
  const std::size_t n = itp::link::encode(r, body);
  REQUIRE(n > 0);
  itp::link::QpSolveReply<D> back;
  REQUIRE(itp::link::decode(std::span<const std::uint8_t>(body.data(), n), back));
  CHECK(back.status == itp::qp::QpStatus::kInfeasible);
  CHECK(back.iterations == 17);
  CHECK(back.objective == -3.25);
  CHECK(back.ticks == 123456789u);
  CHECK(back.x[4] == 2.0);
}
