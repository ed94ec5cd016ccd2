// Banded Cholesky and the LDL' up/down-dates against dense references.
#undef EIGEN_NO_MALLOC  // dense Eigen references allocate; never inside a guard
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <random>
#include <vector>

#include "itp/qp/banded_cholesky.hpp"
#include "itp/qp/ldl_update.hpp"

namespace band = itp::qp::band;
namespace ldl = itp::qp::ldl;

TEST_CASE("banded Cholesky and solves match a dense factorisation") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  constexpr int kBw = 5;
  constexpr int kN = 40;
  for (int n : {1, 2, 6, 17, 40}) {
    double h[kN][kBw + 1] = {};
    double l[kN][kBw + 1] = {};
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) {
      for (int k = 1; k <= kBw && k <= i; ++k) {
        h[i][k] = uni(rng);
        dense(i, i - k) = dense(i - k, i) = h[i][k];
      }
    }
    for (int i = 0; i < n; ++i) {
      h[i][0] = 2.0 * kBw + 1.0 + uni(rng);
      dense(i, i) = h[i][0];
    }
    REQUIRE(band::cholesky(h, l, n, 0.0));
    Eigen::VectorXd b = Eigen::VectorXd::Random(n);
    std::vector<double> x(b.data(), b.data() + n);
    band::forward_solve(l, n, x.data(), 0);
    band::backward_solve(l, n, x.data());
    const Eigen::VectorXd ref = dense.llt().solve(b);
    for (int i = 0; i < n; ++i) CHECK(x[static_cast<std::size_t>(i)] == doctest::Approx(ref(i)).epsilon(1e-12));
    std::vector<double> y(static_cast<std::size_t>(n));
    band::multiply(h, n, x.data(), y.data());
    for (int i = 0; i < n; ++i) CHECK(y[static_cast<std::size_t>(i)] == doctest::Approx(b(i)).epsilon(1e-10));
    // A sparse right-hand side solved from its first nonzero.
    if (n > 3) {
      std::vector<double> e(static_cast<std::size_t>(n), 0.0);
      e[3] = 1.0;
      band::forward_solve(l, n, e.data(), 3);
      const Eigen::MatrixXd lo = dense.llt().matrixL();
      const Eigen::VectorXd ref_e = lo.triangularView<Eigen::Lower>().solve(Eigen::VectorXd::Unit(n, 3));
      for (int i = 0; i < n; ++i) CHECK(e[static_cast<std::size_t>(i)] == doctest::Approx(ref_e(i)).epsilon(1e-12));
    }
  }
}

TEST_CASE("banded Cholesky rejects semidefinite and indefinite matrices") {
  double h[3][2] = {{1, 0}, {1, 1}, {1, 0}};  // [[1,1,0],[1,1,0],[0,0,1]]: singular
  double l[3][2] = {};
  CHECK_FALSE(band::cholesky(h, l, 3, 0.0));
  CHECK(band::cholesky(h, l, 3, 1e-6));  // documented regularisation
  double g[2][2] = {{1, 0}, {1, 2}};      // [[1,2],[2,1]]: eigenvalues 3, -1
  double lg[2][2] = {};
  CHECK_FALSE(band::cholesky(g, lg, 2, 0.0));
}

TEST_CASE("LDL' append and remove track the Gram matrix of the rows") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  constexpr int kDim = 12;
  constexpr int kMax = 9;
  std::vector<Eigen::VectorXd> rows;
  double l[kMax * (kMax - 1) / 2] = {};
  double d[kMax] = {};
  double scratch[kMax] = {};
  auto check = [&]() {
    const int w = static_cast<int>(rows.size());
    if (w == 0) return;
    Eigen::MatrixXd K(w, w);
    for (int i = 0; i < w; ++i) {
      for (int j = 0; j < w; ++j) K(i, j) = rows[static_cast<std::size_t>(i)].dot(rows[static_cast<std::size_t>(j)]);
    }
    Eigen::MatrixXd L = Eigen::MatrixXd::Identity(w, w);
    for (int i = 0; i < w; ++i) {
      for (int j = 0; j < i; ++j) L(i, j) = l[ldl::row_offset(i) + j];
    }
    Eigen::MatrixXd Dm = Eigen::MatrixXd::Zero(w, w);
    for (int i = 0; i < w; ++i) Dm(i, i) = d[i];
    CHECK((L * Dm * L.transpose() - K).cwiseAbs().maxCoeff() < 1e-10);
    // solve
    Eigen::VectorXd b = Eigen::VectorXd::Random(w);
    std::vector<double> x(b.data(), b.data() + w);
    ldl::solve(l, d, w, x.data());
    const Eigen::VectorXd ref = K.ldlt().solve(b);
    for (int i = 0; i < w; ++i) CHECK(x[static_cast<std::size_t>(i)] == doctest::Approx(ref(i)).epsilon(1e-8));
  };
  for (int step = 0; step < 60; ++step) {
    const int w = static_cast<int>(rows.size());
    const bool add = w == 0 || (w < kMax && uni(rng) > -0.2);
    if (add) {
      Eigen::VectorXd r(kDim);
      for (int j = 0; j < kDim; ++j) r(j) = uni(rng);
      std::vector<double> k(static_cast<std::size_t>(w) + 1);
      for (int i = 0; i < w; ++i) k[static_cast<std::size_t>(i)] = rows[static_cast<std::size_t>(i)].dot(r);
      const double piv = ldl::append(l, d, w, k.data(), r.squaredNorm());
      CHECK(piv > 0.0);
      rows.push_back(r);
    } else {
      const int r = static_cast<int>((uni(rng) + 1.0) * 0.5 * w) % w;
      ldl::remove(l, d, w, r, scratch);
      rows.erase(rows.begin() + r);
    }
    check();
  }
}

TEST_CASE("LDL' null vector of a dependent last row spans the dependency") {
  double l[6] = {};
  double d[4] = {};
  const double r0[3] = {1, 2, 0}, r1[3] = {0, 1, 1}, r2[3] = {2, 5, 1};  // r2 = 2 r0 + r1
  const double* rows[3] = {r0, r1, r2};
  for (int w = 0; w < 3; ++w) {
    double k[3] = {};
    for (int i = 0; i < w; ++i) {
      for (int j = 0; j < 3; ++j) k[i] += rows[i][j] * rows[w][j];
    }
    double nn = 0.0;
    for (int j = 0; j < 3; ++j) nn += rows[w][j] * rows[w][j];
    ldl::append(l, d, w, k, nn);
  }
  CHECK(std::abs(d[2]) < 1e-12);
  double p[3] = {};
  ldl::null_vector(l, 3, p);
  CHECK(p[2] == 1.0);
  CHECK(p[0] == doctest::Approx(-2.0));
  CHECK(p[1] == doctest::Approx(-1.0));
}
