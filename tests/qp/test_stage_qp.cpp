// qp::StageQp: a stage restarts from its last solve exactly when its matrix
// key is unchanged: hot while it holds the shared workspace, else warm.
#include <doctest/doctest.h>

#include <memory>
#include <random>

#include "itp/decision/coarse_evaluation.hpp"
#include "itp/path/path_optimizer.hpp"
#include "itp/qp/stage_qp.hpp"
#include "itp/speed/speed_optimizer.hpp"
#include "qp_test_util.hpp"

using namespace itp::qp;

namespace {

using D = QpDims<double, 40, 80, 6, 4>;

struct Key {
  double h = 0;
  double weight = 0;
  bool operator==(const Key&) const = default;
};

// A second shape in the same arena (the planner's three QPs differ in shape).
using D2 = QpDims<double, 24, 30, 4, 2>;
using Arena = QpArena<largest_storage<D, D2>()>;

struct Fixture {
  Arena arena;
  StageQp<D, Key, Arena> stage{arena};
  QpWorkspace<D> ws;  // for independent cold solves
  QpResult<D> cold;
  QpSettings<double> settings;
};

// The stage's problem shape in both tests: n 40, m 80, half-bandwidth 4.
qp_test::BuildOptions stage_options() {
  qp_test::BuildOptions o;
  o.n = 40;
  o.m = 80;
  o.bandwidth = 4;
  o.max_row_nnz = 6;
  o.p_row_active = 0.3;
  return o;
}

}  // namespace

TEST_CASE("StageQp: hot only with the same key; a new key or reset() solves cold, with the cold answer") {
  auto f = std::make_unique<Fixture>();
  std::mt19937 rng(7);
  const qp_test::BuildOptions o = stage_options();
  qp_test::build_random(f->stage.problem(), o, rng);
  const Key a{1.0, 2.0};
  CHECK_FALSE(f->stage.same_matrices(a));  // nothing built yet
  REQUIRE(f->stage.solve(a) == QpStatus::kOptimal);
  CHECK(f->stage.same_matrices(a));
  CHECK_FALSE(f->stage.same_matrices(Key{1.0, 2.5}));
  CHECK_FALSE(f->stage.same_matrices(Key{1.5, 2.0}));

  // Same key, new g: a hotstart, the cold answer in fewer iterations.
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (int j = 0; j < o.n; ++j) f->stage.problem().g[j] += 0.05 * gauss(rng);
  REQUIRE(f->stage.solve(a) == QpStatus::kOptimal);
  REQUIRE(solve_cold(f->stage.problem(), f->ws, f->settings, f->cold) == QpStatus::kOptimal);
  for (int j = 0; j < o.n; ++j) CHECK(f->stage.result().x[j] == doctest::Approx(f->cold.x[j]).epsilon(1e-9));
  CHECK(f->stage.result().iterations < f->cold.iterations);

  // After reset() the same key solves cold: the cold solve's iterations.
  f->stage.reset();
  REQUIRE(f->stage.solve(a) == QpStatus::kOptimal);
  CHECK(f->stage.result().iterations == f->cold.iterations);

  // A new H under a new key: cold, and the new problem's answer.
  qp_test::build_random(f->stage.problem(), o, rng);
  REQUIRE(f->stage.solve(Key{2.0, 2.0}) == QpStatus::kOptimal);
  REQUIRE(solve_cold(f->stage.problem(), f->ws, f->settings, f->cold) == QpStatus::kOptimal);
  CHECK(f->stage.result().iterations == f->cold.iterations);
  for (int j = 0; j < o.n; ++j) CHECK(f->stage.result().x[j] == doctest::Approx(f->cold.x[j]).epsilon(1e-9));
}

TEST_CASE("StageQp in a shared arena: after another stage's claim it builds all again and restarts warm") {
  auto f = std::make_unique<Fixture>();
  auto other = std::make_unique<StageQp<D2, Key, Arena>>(f->arena);
  std::mt19937 rng(11);
  const qp_test::BuildOptions o = stage_options();
  const Key a{1.0, 2.0};
  auto own = std::make_unique<QpProblem<D>>();  // the stage's problem, as its builder would write it
  qp_test::build_random(*own, o, rng);
  f->stage.problem() = *own;
  REQUIRE(f->stage.solve(a) == QpStatus::kOptimal);
  const WorkingSet<D> last = f->stage.result().working_set;
  REQUIRE(last.size > 0);
  CHECK(f->stage.same_matrices(a));

  // The other stage builds and solves its own problem in the arena.
  qp_test::BuildOptions o2;
  o2.n = 24;
  o2.m = 30;
  o2.bandwidth = 2;
  o2.max_row_nnz = 4;
  o2.p_row_active = 0.3;
  qp_test::build_random(other->problem(), o2, rng);
  CHECK_FALSE(f->stage.same_matrices(a));  // the first stage's problem is gone
  REQUIRE(other->solve(Key{3.0, 1.0}) == QpStatus::kOptimal);
  CHECK_FALSE(f->stage.same_matrices(a));

  // The first stage claims it back: sizes 0, its builder writes the whole
  // problem (here with a new g). Same key: a warm start from the last
  // working set, bit for bit what solve_warm gives from it in a workspace of
  // its own, and the cold optimum in fewer iterations.
  CHECK(f->stage.problem().n == 0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (int j = 0; j < o.n; ++j) own->g[j] += 0.05 * gauss(rng);
  f->stage.problem() = *own;
  REQUIRE(f->stage.solve(a) == QpStatus::kOptimal);
  auto warm = std::make_unique<QpResult<D>>();
  REQUIRE(solve_warm(*own, f->ws, f->settings, last, *warm) == QpStatus::kOptimal);
  CHECK(f->stage.result().iterations == warm->iterations);
  for (int j = 0; j < o.n; ++j) CHECK(f->stage.result().x[j] == warm->x[j]);
  REQUIRE(solve_cold(*own, f->ws, f->settings, f->cold) == QpStatus::kOptimal);
  for (int j = 0; j < o.n; ++j) CHECK(f->stage.result().x[j] == doctest::Approx(f->cold.x[j]).epsilon(1e-9));
  CHECK(f->stage.result().iterations < f->cold.iterations);

  // Holding it again, the next solve with the same key is a hotstart: bit
  // for bit that warm solve followed by solve_hot in a workspace of its own.
  auto ws2 = std::make_unique<QpWorkspace<D>>();
  auto seq = std::make_unique<QpResult<D>>();
  REQUIRE(solve_warm(*own, *ws2, f->settings, last, *seq) == QpStatus::kOptimal);
  for (int j = 0; j < o.n; ++j) own->g[j] += 0.05 * gauss(rng);
  CHECK(f->stage.same_matrices(a));
  for (int j = 0; j < o.n; ++j) f->stage.problem().g[j] = own->g[j];
  REQUIRE(f->stage.solve(a) == QpStatus::kOptimal);
  REQUIRE(solve_hot(*own, *ws2, f->settings, *seq) == QpStatus::kOptimal);
  CHECK(f->stage.result().iterations == seq->iterations);
  for (int j = 0; j < o.n; ++j) CHECK(f->stage.result().x[j] == seq->x[j]);
}

TEST_CASE("the planner stages' matrix keys differ when any field differs") {
  using itp::path::PathMatrixKey;
  const PathMatrixKey p{5.0, 3.8, 1.0, {}};
  PathMatrixKey q = p;
  CHECK(p == q);
  q.h = 5.5;                   CHECK_FALSE(p == q); q = p;
  q.front_reach = 3.9;         CHECK_FALSE(p == q); q = p;
  q.rear_reach = 1.1;          CHECK_FALSE(p == q); q = p;
  q.weights.target *= 2;       CHECK_FALSE(p == q); q = p;
  q.weights.d1 *= 2;           CHECK_FALSE(p == q); q = p;
  q.weights.d2 *= 2;           CHECK_FALSE(p == q); q = p;
  q.weights.d3 *= 2;           CHECK_FALSE(p == q); q = p;
  q.weights.obstacle *= 2;     CHECK_FALSE(p == q);
  using itp::speed::SpeedMatrixKey;
  const SpeedMatrixKey s{0.5, {}};
  SpeedMatrixKey t = s;
  t.h = 0.6;                   CHECK_FALSE(s == t); t = s;
  t.weights.s_up *= 2;         CHECK_FALSE(s == t); t = s;
  t.weights.v *= 2;            CHECK_FALSE(s == t); t = s;
  t.weights.a *= 2;            CHECK_FALSE(s == t); t = s;
  t.weights.jerk *= 2;         CHECK_FALSE(s == t);
  using itp::decision::CoarseQpWeights;
  const CoarseQpWeights c{};
  CoarseQpWeights e = c;
  e.l_smooth *= 2;             CHECK_FALSE(c == e); e = c;
  e.l_ref *= 2;                CHECK_FALSE(c == e); e = c;
  e.t_smooth *= 2;             CHECK_FALSE(c == e); e = c;
  e.t_lb *= 2;                 CHECK_FALSE(c == e);
}
