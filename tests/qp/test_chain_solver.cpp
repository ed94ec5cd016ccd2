// The chain solver (qp/chain_qp.hpp) against independent references: the KKT
// conditions (qp/kkt.hpp, problem data only), a brute force over every face of
// small chains (dense equality solves written here), and the general
// active-set solver's objective. Plus the verdicts: what it cannot prove goes
// to the general solver, never a wrong kOptimal.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "heap_guard.hpp"
#include "itp/qp/chain_qp.hpp"
#include "itp/qp/kkt.hpp"
#include "itp/qp/qp.hpp"
#include "itp/qp/stage_qp.hpp"

using namespace itp::qp;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Two interleaved chains of up to 20 (the coarse QP's shape), and one chain.
using Two = QpDims<double, 40, 20, 2, 4, 20>;
using One = QpDims<double, 12, 12, 2, 2, 12>;

template <class D>
struct Case {
  QpProblem<D> p;
  QpResult<D> chain;
  QpResult<D> general;
  QpWorkspace<D> ws;
  QpSettings<typename D::Scalar> settings;
};

// A random chain QP with a known feasible point: H = w2 D2'D2 + w1 D1'D1 +
// diag, per chain; bounds and links around a random walk x*, some one-sided,
// some tight, some fixed; g pulls away from x* so that constraints bind.
template <class D>
void build_chain(QpProblem<D>& p, int n, int stride, std::mt19937& rng, bool tight_links) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  REQUIRE(p.reset(n, 0));
  std::vector<double> xs(static_cast<std::size_t>(n));
  for (int c = 0; c < stride; ++c) {
    double walk = 2.0 * u(rng) - 1.0;
    for (int j = c; j < n; j += stride) {
      walk += tight_links ? 0.3 : 2.0 * u(rng) - 1.0;
      xs[static_cast<std::size_t>(j)] = walk;
    }
  }
  const double w2 = 0.1 + 10.0 * u(rng), w1 = 2.0 * u(rng);
  for (int j = 0; j < n; ++j) {
    const double d = 0.01 + u(rng);
    REQUIRE(p.set_hessian(j, j, p.hessian(j, j) + d));
    if (j + 2 * stride < n) {  // w2 (x_j - 2 x_{j+k} + x_{j+2k})^2
      const int idx[3] = {j, j + stride, j + 2 * stride};
      const double co[3] = {1.0, -2.0, 1.0};
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b <= a; ++b) {
          REQUIRE(p.set_hessian(idx[a], idx[b], p.hessian(idx[a], idx[b]) + 2.0 * w2 * co[a] * co[b]));
        }
      }
    }
    if (j + stride < n) {  // w1 (x_{j+k} - x_j)^2
      REQUIRE(p.set_hessian(j, j, p.hessian(j, j) + 2.0 * w1));
      REQUIRE(p.set_hessian(j + stride, j + stride, p.hessian(j + stride, j + stride) + 2.0 * w1));
      REQUIRE(p.set_hessian(j + stride, j, p.hessian(j + stride, j) - 2.0 * w1));
    }
    p.g[j] = 20.0 * (u(rng) - 0.5);
    const double x = xs[static_cast<std::size_t>(j)];
    const double kind = u(rng);
    if (kind < 0.1) {
      p.lb[j] = p.ub[j] = x;  // fixed
    } else {
      p.lb[j] = kind < 0.4 ? x - 0.5 * u(rng) : (kind < 0.6 ? -kInf : x);
      p.ub[j] = kind < 0.7 ? x + 0.5 * u(rng) : kInf;
    }
  }
  int m = 0;
  std::array<int, 64> first{};
  for (int j = 0; j + stride < n && m < D::kMaxRows; ++j) {
    if (u(rng) < 0.3) continue;  // no link here
    first[static_cast<std::size_t>(m)] = j;
    ++m;
  }
  p.m = m;
  for (int r = 0; r < m; ++r) {
    const int j = first[static_cast<std::size_t>(r)];
    const double v = 0.5 + u(rng);  // row v (x_{j+k} - x_j)
    REQUIRE(p.push_row_entry(r, j, -v));
    REQUIRE(p.push_row_entry(r, j + stride, v));
    const double d = v * (xs[static_cast<std::size_t>(j + stride)] - xs[static_cast<std::size_t>(j)]);
    const double kind = u(rng);
    p.lba[r] = kind < 0.5 ? d - (tight_links ? 0.0 : 0.3 * u(rng)) : -kInf;
    p.uba[r] = kind < 0.3 || kind >= 0.5 ? d + 0.3 * u(rng) : kInf;
  }
}

template <class D>
double objective(const QpProblem<D>& p, const double* x) {
  double hx[D::kMaxVariables];
  band::multiply(p.h_band, p.n, x, hx);
  double f = 0;
  for (int j = 0; j < p.n; ++j) f += x[j] * (0.5 * hx[j] + p.g[j]);
  return f;
}

// Minimum over every face: each bound and row lower, upper or inactive; the
// equality-constrained optimum of a face (dense KKT system, Gaussian
// elimination) counts when it is feasible. The global optimum of a convex QP
// is the optimum of the face it lies on.
template <class D>
double brute_force_optimum(const QpProblem<D>& p) {
  const int n = p.n, c = n + p.m;
  std::vector<int> state(static_cast<std::size_t>(c), 0);
  double best = kInf;
  auto row = [&](int k, std::vector<double>& a, double& lo, double& hi) {
    std::fill(a.begin(), a.end(), 0.0);
    if (k < n) {
      a[static_cast<std::size_t>(k)] = 1;
      lo = p.lb[k];
      hi = p.ub[k];
    } else {
      const int r = k - n;
      for (int e = 0; e < p.a_nnz[r]; ++e) a[p.a_col[r][e]] = p.a_val[r][e];
      lo = p.lba[r];
      hi = p.uba[r];
    }
  };
  std::vector<double> a(static_cast<std::size_t>(n));
  for (;;) {
    std::vector<std::vector<double>> rows;
    std::vector<double> rhs;
    bool usable = true;
    for (int k = 0; k < c && usable; ++k) {
      if (state[static_cast<std::size_t>(k)] == 0) continue;
      double lo = 0, hi = 0;
      row(k, a, lo, hi);
      const double b = state[static_cast<std::size_t>(k)] < 0 ? lo : hi;
      usable = std::isfinite(b);
      rows.push_back(a);
      rhs.push_back(b);
    }
    const int w = static_cast<int>(rows.size());
    if (usable && w <= n) {
      const int s = n + w;  // [H A'; A 0] [x; y] = [-g; b]
      std::vector<double> m(static_cast<std::size_t>(s * (s + 1)), 0.0);
      auto at = [&](int i, int j) -> double& { return m[static_cast<std::size_t>(i * (s + 1) + j)]; };
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) at(i, j) = p.hessian(i, j);
        at(i, s) = -p.g[i];
      }
      for (int r = 0; r < w; ++r) {
        for (int j = 0; j < n; ++j) at(n + r, j) = at(j, n + r) = rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(j)];
        at(n + r, s) = rhs[static_cast<std::size_t>(r)];
      }
      bool singular = false;
      for (int col = 0; col < s && !singular; ++col) {
        int piv = col;
        for (int i = col + 1; i < s; ++i) if (std::abs(at(i, col)) > std::abs(at(piv, col))) piv = i;
        if (std::abs(at(piv, col)) < 1e-12) {
          singular = true;
          break;
        }
        for (int j = 0; j <= s; ++j) std::swap(at(col, j), at(piv, j));
        for (int i = 0; i < s; ++i) {
          if (i == col) continue;
          const double f = at(i, col) / at(col, col);
          for (int j = col; j <= s; ++j) at(i, j) -= f * at(col, j);
        }
      }
      if (!singular) {
        std::vector<double> x(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) x[static_cast<std::size_t>(i)] = at(i, s) / at(i, i);
        bool feasible = true;
        for (int k = 0; k < c && feasible; ++k) {
          double lo = 0, hi = 0;
          row(k, a, lo, hi);
          double v = 0;
          for (int j = 0; j < n; ++j) v += a[static_cast<std::size_t>(j)] * x[static_cast<std::size_t>(j)];
          feasible = v >= lo - 1e-9 * (1 + std::abs(lo)) && v <= hi + 1e-9 * (1 + std::abs(hi));
        }
        if (feasible) best = std::min(best, objective(p, x.data()));
      }
    }
    int k = 0;  // next state: odometer over {0, -1, +1}
    while (k < c && state[static_cast<std::size_t>(k)] == 1) state[static_cast<std::size_t>(k++)] = 0;
    if (k == c) break;
    state[static_cast<std::size_t>(k)] = state[static_cast<std::size_t>(k)] == 0 ? -1 : 1;
  }
  return best;
}

template <class D>
void check_against_general(Case<D>& k) {
  ChainVerdict verdict;
  {
    test_support::HeapGuard guard;
    verdict = solve_chain(k.p, k.ws, k.settings, k.chain);
  }
  const QpStatus general = solve_cold(k.p, k.ws, k.settings, k.general);
  if (verdict == ChainVerdict::kUseGeneralSolver) {
    // Only what the chain solver may not settle: never a solvable problem it dropped silently.
    CHECK(general != QpStatus::kOptimal);
    return;
  }
  REQUIRE(k.chain.status == QpStatus::kOptimal);
  REQUIRE(general == QpStatus::kOptimal);
  const KktResidual<double> r = kkt_residual(k.p, k.chain);
  CHECK(r.max() <= 1e-8);
  CHECK(k.chain.objective == doctest::Approx(k.general.objective).epsilon(1e-9));
  CHECK(k.chain.objective == doctest::Approx(objective(k.p, k.chain.x)).epsilon(1e-12));
}

}  // namespace

TEST_CASE("chain solver: random chains, one and two interleaved, meet KKT and the general solver's optimum") {
  auto k2 = std::make_unique<Case<Two>>();
  auto k1 = std::make_unique<Case<One>>();
  std::mt19937 rng(11);
  int settled = 0, total = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const bool tight = trial % 3 == 0;  // links at their bound along a run: degenerate vertices
    if (trial % 2 == 0) {
      build_chain(k2->p, 10 + trial % 31, 2, rng, tight);
      check_against_general(*k2);
      settled += k2->chain.status == QpStatus::kOptimal;
    } else {
      build_chain(k1->p, 3 + trial % 10, 1, rng, tight);
      check_against_general(*k1);
      settled += k1->chain.status == QpStatus::kOptimal;
    }
    ++total;
  }
  // Infeasible random draws go to the general solver; the rest must be settled here.
  CHECK(settled >= total * 3 / 4);
}

TEST_CASE("chain solver: the coarse QP of the planner (degenerate time chain) is solved as by the general solver") {
  auto k = std::make_unique<Case<Two>>();
  // t_i >= i dt and t_{i+1} - t_i >= dt: bound and link tight together at every sample.
  REQUIRE(k->p.reset(40, 19));
  for (int i = 0; i < 20; ++i) {
    const int l = 2 * i, t = 2 * i + 1;
    k->p.set_hessian(l, l, 0.1);
    k->p.set_hessian(t, t, 2.0);
    k->p.g[l] = -0.1 * 1.5;
    k->p.g[t] = -2.0 * 0.3 * i;
    k->p.lb[l] = -0.8;
    k->p.ub[l] = i > 8 && i < 13 ? 0.5 : 4.3;
    k->p.lb[t] = 0.3 * i;
  }
  for (int i = 1; i + 1 < 20; ++i) {
    const int l = 2 * i, t = 2 * i + 1;
    {
      for (int v : {l, t}) {
        const int idx[3] = {v - 2, v, v + 2};
        const double co[3] = {1, -2, 1};
        for (int a = 0; a < 3; ++a) {
          for (int b = 0; b <= a; ++b) k->p.set_hessian(idx[a], idx[b], k->p.hessian(idx[a], idx[b]) + 20 * co[a] * co[b]);
        }
      }
    }
  }
  k->p.lb[0] = k->p.ub[0] = 1.0;
  k->p.lb[1] = k->p.ub[1] = 0.0;
  for (int r = 0; r < 19; ++r) {
    REQUIRE(k->p.push_row_entry(r, 2 * r + 1, -1));
    REQUIRE(k->p.push_row_entry(r, 2 * r + 3, 1));
    k->p.lba[r] = 0.3;
  }
  check_against_general(*k);
  CHECK(k->chain.status == QpStatus::kOptimal);
}

TEST_CASE("chain solver: verdicts. Invalid data settled as such; other shapes, infeasibility, indefinite H and the cap go on") {
  auto k = std::make_unique<Case<Two>>();
  std::mt19937 rng(9);
  auto valid = [&] {
    build_chain(k->p, 40, 2, rng, false);
    for (int j = 0; j < 40; ++j) k->p.lb[j] = -kInf, k->p.ub[j] = kInf;
    k->p.lb[0] = k->p.ub[0] = 0.0;
  };
  valid();
  k->p.g[5] = std::numeric_limits<double>::quiet_NaN();
  CHECK(solve_chain(k->p, k->ws, k->settings, k->chain) == ChainVerdict::kSettled);
  CHECK(k->chain.status == QpStatus::kInvalidInput);

  valid();
  k->p.set_hessian(3, 2, 0.01);  // couples the two chains: not chain form
  CHECK(solve_chain(k->p, k->ws, k->settings, k->chain) ==
        ChainVerdict::kUseGeneralSolver);

  valid();
  k->p.set_hessian(7, 7, -50.0);  // a negative eigenvalue: the general solver proves it
  CHECK(solve_chain(k->p, k->ws, k->settings, k->chain) ==
        ChainVerdict::kUseGeneralSolver);
  CHECK(solve_cold(k->p, k->ws, k->settings, k->general) == QpStatus::kNotConvex);

  valid();  // x_2 <= 0, x_2 + 2 links of >= 1 reach x_6 >= 2 > ub: infeasible through the chain
  k->p.m = 2;
  for (int r = 0; r < 2; ++r) {
    k->p.a_nnz[r] = 0;
    REQUIRE(k->p.push_row_entry(r, 2 + 2 * r, -1));
    REQUIRE(k->p.push_row_entry(r, 4 + 2 * r, 1));
    k->p.lba[r] = 1.0;
    k->p.uba[r] = kInf;
  }
  k->p.lb[2] = k->p.ub[2] = 0.0;
  k->p.ub[6] = 1.5;
  CHECK(solve_chain(k->p, k->ws, k->settings, k->chain) ==
        ChainVerdict::kUseGeneralSolver);
  CHECK(solve_cold(k->p, k->ws, k->settings, k->general) == QpStatus::kInfeasible);

  // A cap below what the problem needs: handed on, never reported optimal.
  int capped = 0;
  for (int trial = 0; trial < 40; ++trial) {
    build_chain(k->p, 40, 2, rng, true);
    QpSettings<double> one = k->settings;
    one.max_iterations = 1;
    if (solve_chain(k->p, k->ws, one, k->chain) == ChainVerdict::kSettled) {
      CHECK(k->chain.iterations <= 1);
      CHECK(kkt_residual(k->p, k->chain).max() <= 1e-8);
    } else {
      ++capped;
    }
  }
  CHECK(capped > 0);
}

TEST_CASE("chain solver: it borrows the workspace's M_W rows, so a factor held before it is dropped, settled or handed on") {
  auto k = std::make_unique<Case<Two>>();
  auto fresh = std::make_unique<Case<Two>>();
  std::mt19937 rng(33);
  int handed_on = 0;
  for (int trial = 0; trial < 20; ++trial) {
    build_chain(k->p, 40, 2, rng, true);
    REQUIRE(solve_cold(k->p, k->ws, k->settings, k->general) == QpStatus::kOptimal);
    REQUIRE(k->ws.factored);
    // A cap of one change hands most of these on after the chains' data
    // went into M_W; a hot start must then refuse, not use the rows.
    QpSettings<double> settings = k->settings;
    settings.max_iterations = trial % 2 == 0 ? 1 : 0;
    const ChainVerdict v = solve_chain(k->p, k->ws, settings, k->chain);
    handed_on += v == ChainVerdict::kUseGeneralSolver ? 1 : 0;
    CHECK_FALSE(k->ws.factored);
    CHECK(solve_hot(k->p, k->ws, k->settings, k->general) == QpStatus::kNotFactored);
    // The general solver after it: bit for bit as on a workspace never lent.
    fresh->p = k->p;
    REQUIRE(solve_cold(k->p, k->ws, k->settings, k->general) == QpStatus::kOptimal);
    REQUIRE(solve_cold(fresh->p, fresh->ws, fresh->settings, fresh->general) == QpStatus::kOptimal);
    for (int j = 0; j < 40; ++j) CHECK(k->general.x[j] == fresh->general.x[j]);
  }
  CHECK(handed_on > 0);
}

TEST_CASE("chain solver: a StageQp of chain shape hands what the chain solver leaves to the general solver") {
  using Arena = QpArena<largest_storage<Two>()>;
  struct Key {
    int v = 0;
    bool operator==(const Key&) const = default;
  };
  auto arena = std::make_unique<Arena>();
  auto stage = std::make_unique<StageQp<Two, Key, Arena>>(*arena);
  auto ref = std::make_unique<Case<Two>>();
  std::mt19937 rng(21);
  for (int trial = 0; trial < 60; ++trial) {
    build_chain(ref->p, 40, 2, rng, trial % 2 == 0);
    stage->problem() = ref->p;
    const QpStatus st = stage->solve(Key{trial % 3});
    const QpStatus general = solve_cold(ref->p, ref->ws, ref->settings, ref->general);
    CHECK(st == general);
    if (st == QpStatus::kOptimal) {
      CHECK(stage->result().objective == doctest::Approx(ref->general.objective).epsilon(1e-9));
      CHECK(kkt_residual(ref->p, stage->result()).max() <= 1e-8);
    }
  }
}

TEST_CASE("chain solver: in float (the low-RAM image) it agrees with the general float solver") {
  using TwoF = QpDims<float, 40, 20, 2, 4, 20>;
  auto k = std::make_unique<Case<Two>>();
  auto f = std::make_unique<Case<TwoF>>();
  std::mt19937 rng(17);
  int compared = 0;
  for (int trial = 0; trial < 100; ++trial) {
    build_chain(k->p, 40, 2, rng, trial % 2 == 0);
    REQUIRE(f->p.reset(k->p.n, k->p.m));
    for (int i = 0; i < k->p.n; ++i) {
      for (int off = 0; off <= 4 && off <= i; ++off) f->p.h_band[i][off] = static_cast<float>(k->p.h_band[i][off]);
      f->p.g[i] = static_cast<float>(k->p.g[i]);
      f->p.lb[i] = static_cast<float>(k->p.lb[i]);
      f->p.ub[i] = static_cast<float>(k->p.ub[i]);
    }
    for (int r = 0; r < k->p.m; ++r) {
      for (int e = 0; e < k->p.a_nnz[r]; ++e) {
        REQUIRE(f->p.push_row_entry(r, k->p.a_col[r][e], static_cast<float>(k->p.a_val[r][e])));
      }
      f->p.lba[r] = static_cast<float>(k->p.lba[r]);
      f->p.uba[r] = static_cast<float>(k->p.uba[r]);
    }
    const QpStatus general = solve_cold(f->p, f->ws, f->settings, f->general);
    const ChainVerdict v = solve_chain(f->p, f->ws, f->settings, f->chain);
    if (v == ChainVerdict::kUseGeneralSolver || general != QpStatus::kOptimal) continue;
    REQUIRE(f->chain.status == QpStatus::kOptimal);
    float scale = 1.0f;
    for (int i = 0; i < f->p.n; ++i) scale = std::max(scale, std::abs(f->p.g[i]));
    CHECK(kkt_residual(f->p, f->chain).max() <= 1e-3f * scale);
    CHECK(f->chain.objective == doctest::Approx(f->general.objective).epsilon(1e-4));
    ++compared;
  }
  CHECK(compared >= 50);
}

namespace {

// A random working set over the problem's bounds and rows (a guess that is
// mostly wrong), for warm starts.
template <class D>
void random_working_set(const QpProblem<D>& p, std::mt19937& rng, WorkingSet<D>& w) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  w.clear();
  for (int j = 0; j < p.n; ++j) {
    if (u(rng) < 0.3) static_cast<void>(w.push(j, true, u(rng) < 0.5 ? -1 : 1));
  }
  for (int r = 0; r < p.m; ++r) {
    if (u(rng) < 0.3) static_cast<void>(w.push(r, false, u(rng) < 0.5 ? -1 : 1));
  }
}

// g and the bounds moved, H and A kept (what a planner restart changes).
template <class D>
void move_vectors(QpProblem<D>& p, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int j = 0; j < p.n; ++j) {
    p.g[j] += 2.0 * u(rng);
    if (p.lb[j] < p.ub[j]) {  // fixed stay fixed
      const double shift = 0.2 * u(rng);
      p.lb[j] += shift;
      p.ub[j] += shift;
    }
  }
}

}  // namespace

// Warm solves of k.p (k.general: its optimum by the general solver) from
// three working sets: the optimal one, a random one and other.chain's. Each
// one the chain solver settles is checked against the KKT conditions and the
// general solver's objective.
struct WarmTally {
  int settled = 0;  // of the three starts
  bool direct = false;  // from the optimal set: one equality solve per chain, no change
};
WarmTally warm_from_three_starts(Case<Two>& k, const Case<Two>& other, std::mt19937& rng) {
  auto warm = std::make_unique<QpResult<Two>>();
  auto guess = std::make_unique<WorkingSet<Two>>();
  WarmTally tally;
  for (int start = 0; start < 3; ++start) {
    if (start == 0) *guess = k.general.working_set;
    if (start == 1) random_working_set(k.p, rng, *guess);
    if (start == 2) *guess = other.chain.working_set;
    ChainVerdict v;
    {
      test_support::HeapGuard heap;
      v = solve_chain(k.p, k.ws, k.settings, *warm, guess.get());
    }
    if (v == ChainVerdict::kUseGeneralSolver) continue;  // allowed, never a wrong answer
    REQUIRE(warm->status == QpStatus::kOptimal);
    CHECK(kkt_residual(k.p, *warm).max() <= 1e-8);
    CHECK(warm->objective == doctest::Approx(k.general.objective).epsilon(1e-9));
    ++tally.settled;
    if (start == 0) tally.direct = warm->refactorisations == 2 && warm->iterations == 0;
  }
  return tally;
}

TEST_CASE("chain solver: warm starts from the optimal, a random and another problem's working set agree with the general solver") {
  auto k = std::make_unique<Case<Two>>();
  auto other = std::make_unique<Case<Two>>();
  std::mt19937 rng(31);
  int compared = 0, direct = 0;
  for (int trial = 0; trial < 150; ++trial) {
    build_chain(k->p, 20 + trial % 21, 2, rng, trial % 3 == 0);
    build_chain(other->p, k->p.n, 2, rng, trial % 3 == 1);
    const QpStatus general = solve_cold(k->p, k->ws, k->settings, k->general);
    if (general != QpStatus::kOptimal) continue;
    static_cast<void>(solve_chain(other->p, other->ws, other->settings, other->chain));
    const WarmTally t = warm_from_three_starts(*k, *other, rng);
    compared += t.settled;
    direct += t.direct ? 1 : 0;  // from the optimal working set each chain needs one equality solve
  }
  CHECK(compared >= 300);
  CHECK(direct >= 90);
}

TEST_CASE("chain solver: box chains (bounds only) warm from the optimal, a random and another problem's working set agree with the general solver") {
  // On a chain without link rows the guess is tested by one exchange round;
  // if it does not stand, it filters the clamped cold start (only the bounds
  // it holds too stay marked) and the primal loop goes on from there. x stays
  // feasible on the marks, so every answer must still be the optimum.
  auto k = std::make_unique<Case<Two>>();
  auto other = std::make_unique<Case<Two>>();
  std::mt19937 rng(57);
  int compared = 0, one_per_chain = 0;
  for (int trial = 0; trial < 150; ++trial) {
    build_chain(k->p, 20 + trial % 21, 2, rng, false);
    build_chain(other->p, k->p.n, 2, rng, false);
    k->p.m = other->p.m = 0;  // bounds only
    const QpStatus general = solve_cold(k->p, k->ws, k->settings, k->general);
    REQUIRE(general == QpStatus::kOptimal);  // a box around a point: feasible, H positive definite
    REQUIRE(solve_chain(other->p, other->ws, other->settings, other->chain) == ChainVerdict::kSettled);
    const WarmTally t = warm_from_three_starts(*k, *other, rng);
    compared += t.settled;
    // From the optimal working set one exchange round per chain settles it
    // (without it, the cold start adds the bounds one blocked step each).
    one_per_chain += t.direct ? 1 : 0;
  }
  CHECK(compared == 450);  // every start settled by the chain solver
  CHECK(one_per_chain >= 150 * 9 / 10);
}

TEST_CASE("chain solver: small chains, cold and warm from random working sets, against a brute force over every face") {
  auto k = std::make_unique<Case<One>>();
  auto guess = std::make_unique<WorkingSet<One>>();
  std::mt19937 rng(5);         // the problems
  std::mt19937 guess_rng(41);  // the warm starts' guesses
  int compared = 0, warm_compared = 0;
  for (int trial = 0; trial < 60; ++trial) {
    build_chain(k->p, 3 + trial % 3, 1, rng, trial % 2 == 0);
    const double best = brute_force_optimum(k->p);
    const ChainVerdict v = solve_chain(k->p, k->ws, k->settings, k->chain);
    if (!std::isfinite(best)) {  // infeasible: not for the chain solver to say
      CHECK(v == ChainVerdict::kUseGeneralSolver);
      continue;
    }
    REQUIRE(v == ChainVerdict::kSettled);
    REQUIRE(k->chain.status == QpStatus::kOptimal);
    CHECK(k->chain.objective == doctest::Approx(best).epsilon(1e-8));
    ++compared;
    random_working_set(k->p, guess_rng, *guess);
    if (solve_chain(k->p, k->ws, k->settings, k->chain, guess.get()) != ChainVerdict::kSettled) continue;
    REQUIRE(k->chain.status == QpStatus::kOptimal);
    CHECK(k->chain.objective == doctest::Approx(best).epsilon(1e-8));
    ++warm_compared;
  }
  CHECK(compared >= 30);
  CHECK(warm_compared >= 25);
}

TEST_CASE("chain solver: hot starts (same H and A) agree with the general solver; the checks of H and A are skipped only after a settled chain solve") {
  auto k = std::make_unique<Case<Two>>();    // the chain solver's workspace
  auto ref = std::make_unique<Case<Two>>();  // the general solver's, apart
  std::mt19937 rng(43);
  int hot = 0;
  for (int trial = 0; trial < 80; ++trial) {
    build_chain(k->p, 40, 2, rng, trial % 2 == 0);
    if (solve_chain(k->p, k->ws, k->settings, k->chain) != ChainVerdict::kSettled) continue;
    REQUIRE(k->ws.chain_stride == 2);
    const WorkingSet<Two> last = k->chain.working_set;
    move_vectors(k->p, rng);  // a restart: new g and bounds on the same H and A
    ref->p = k->p;
    const QpStatus general = solve_cold(ref->p, ref->ws, ref->settings, ref->general);
    const ChainVerdict v = solve_chain(k->p, k->ws, k->settings, k->chain, &last, true);
    if (v == ChainVerdict::kUseGeneralSolver) {
      CHECK(general != QpStatus::kOptimal);
      continue;
    }
    REQUIRE(k->chain.status == QpStatus::kOptimal);
    REQUIRE(general == QpStatus::kOptimal);
    CHECK(kkt_residual(k->p, k->chain).max() <= 1e-8);
    CHECK(k->chain.objective == doctest::Approx(ref->general.objective).epsilon(1e-9));
    ++hot;
  }
  CHECK(hot >= 30);

  // g and the bounds are still checked on a hot start.
  build_chain(k->p, 40, 2, rng, false);
  REQUIRE(solve_chain(k->p, k->ws, k->settings, k->chain) == ChainVerdict::kSettled);
  const WorkingSet<Two> last = k->chain.working_set;
  k->p.g[3] = std::numeric_limits<double>::quiet_NaN();
  CHECK(solve_chain(k->p, k->ws, k->settings, k->chain, &last, true) == ChainVerdict::kSettled);
  CHECK(k->chain.status == QpStatus::kInvalidInput);
  // A hot call on other sizes than the settled solve's checks H again.
  build_chain(k->p, 40, 2, rng, false);
  REQUIRE(solve_chain(k->p, k->ws, k->settings, k->chain) == ChainVerdict::kSettled);
  build_chain(k->p, 36, 2, rng, false);
  k->p.h_band[7][0] = std::numeric_limits<double>::quiet_NaN();
  CHECK(solve_chain(k->p, k->ws, k->settings, k->chain, &last, true) == ChainVerdict::kSettled);
  CHECK(k->chain.status == QpStatus::kInvalidInput);
  // After a general solve in the workspace (no chain solve to rely on) a hot
  // call checks H again.
  build_chain(k->p, 40, 2, rng, false);
  REQUIRE(solve_chain(k->p, k->ws, k->settings, k->chain) == ChainVerdict::kSettled);
  static_cast<void>(solve_cold(k->p, k->ws, k->settings, k->general));
  CHECK(k->ws.chain_stride == 0);
  k->p.h_band[7][0] = std::numeric_limits<double>::quiet_NaN();
  CHECK(solve_chain(k->p, k->ws, k->settings, k->chain, &last, true) == ChainVerdict::kSettled);
  CHECK(k->chain.status == QpStatus::kInvalidInput);
}

TEST_CASE("chain solver: bounds implied by the links left of them never enter the working set (the coarse QP's time staircase)") {
  auto k = std::make_unique<Case<One>>();
  // x_0 = 0, x_q >= 0.3 q (the staircase) and x_{q+1} - x_q >= 0.3: every
  // bound past the first follows from the links; g pulls every x below it.
  REQUIRE(k->p.reset(12, 11));
  for (int q = 0; q < 12; ++q) {
    k->p.set_hessian(q, q, 1.0);
    k->p.g[q] = 1.0;
    k->p.lb[q] = 0.3 * q;
    k->p.ub[q] = kInf;
  }
  k->p.ub[0] = 0.0;
  for (int r = 0; r < 11; ++r) {
    REQUIRE(k->p.push_row_entry(r, r, -1));
    REQUIRE(k->p.push_row_entry(r, r + 1, 1));
    k->p.lba[r] = 0.3;
    k->p.uba[r] = kInf;
  }
  REQUIRE(solve_chain(k->p, k->ws, k->settings, k->chain) == ChainVerdict::kSettled);
  REQUIRE(k->chain.status == QpStatus::kOptimal);
  CHECK(kkt_residual(k->p, k->chain).max() <= 1e-10);
  for (int q = 0; q < 12; ++q) CHECK(k->chain.x[q] == doctest::Approx(0.3 * q).epsilon(1e-12));  // analytic
  int bounds = 0, links = 0;
  for (int i = 0; i < k->chain.working_set.size; ++i) {
    const ActiveConstraint& e = k->chain.working_set.entries[i];
    if (e.is_bound != 0 && e.index > 0) ++bounds;
    if (e.is_bound == 0) ++links;
  }
  CHECK(bounds == 0);
  CHECK(links == 11);
}
