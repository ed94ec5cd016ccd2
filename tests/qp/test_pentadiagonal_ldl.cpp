// The pentadiagonal LDL' (qp/pentadiagonal_ldl.hpp) against a dense
// reference written here: the residual |A y - b| of its solve, with A built
// as B B' + diag (positive definite, pentadiagonal for a tridiagonal B) so
// that the matrices are far from diagonally dominant, and its refusal of
// matrices that are not positive definite.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "itp/qp/pentadiagonal_ldl.hpp"

namespace {

struct Penta {
  int n = 0;
  std::vector<double> dense;              // n x n, row major
  double band[40][3] = {};                // {A(i,i), A(i,i-1), A(i,i-2)}
  double at(int i, int j) const { return dense[static_cast<std::size_t>(i * n + j)]; }
};

// A = B B' + d I with B lower bidiagonal plus one subdiagonal below: B B' has
// half-bandwidth 2.
Penta random_spd(int n, std::mt19937& rng, double shift) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> b(static_cast<std::size_t>(n * n), 0.0);
  for (int i = 0; i < n; ++i) {
    b[static_cast<std::size_t>(i * n + i)] = 1.0 + u(rng);
    if (i >= 1) b[static_cast<std::size_t>(i * n + i - 1)] = 3.0 * u(rng);
  }
  Penta p;
  p.n = n;
  p.dense.assign(static_cast<std::size_t>(n * n), 0.0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      double s = i == j ? shift : 0.0;
      for (int k = 0; k < n; ++k) s += b[static_cast<std::size_t>(i * n + k)] * b[static_cast<std::size_t>(j * n + k)];
      p.dense[static_cast<std::size_t>(i * n + j)] = s;
    }
  }
  for (int i = 0; i < n; ++i) {
    p.band[i][0] = p.at(i, i);
    p.band[i][1] = i >= 1 ? p.at(i, i - 1) : 0.0;
    p.band[i][2] = i >= 2 ? p.at(i, i - 2) : 0.0;
  }
  return p;
}

}  // namespace

TEST_CASE("pentadiagonal LDL': solves to rounding against a dense product, in place too, for 1 to 40 rows") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + trial % 40;
    Penta p = random_spd(n, rng, 1e-3);
    double f[40][3];
    std::vector<double> b(static_cast<std::size_t>(n)), y(static_cast<std::size_t>(n));
    for (double& v : b) v = 10.0 * u(rng);
    y = b;
    const bool in_place = trial % 2 == 0;
    double (*out)[3] = in_place ? p.band : f;
    REQUIRE(itp::qp::penta::factor(p.band, out, n));
    itp::qp::penta::solve(out, n, y.data());
    double residual = 0, scale = 0;
    for (int i = 0; i < n; ++i) {
      double s = 0, mag = 0;
      for (int j = 0; j < n; ++j) {
        s += p.at(i, j) * y[static_cast<std::size_t>(j)];
        mag += std::abs(p.at(i, j) * y[static_cast<std::size_t>(j)]);
      }
      residual = std::max(residual, std::abs(s - b[static_cast<std::size_t>(i)]));
      scale = std::max(scale, mag + std::abs(b[static_cast<std::size_t>(i)]));
    }
    CHECK(residual <= 1e-12 * scale);
  }
}

TEST_CASE("pentadiagonal LDL': refuses a matrix that is not positive definite, and NaN") {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 100; ++trial) {
    const int n = 3 + trial % 30;
    Penta p = random_spd(n, rng, 1e-3);
    double f[40][3];
    // Minus a multiple of I beyond the smallest eigenvalue (at most the
    // smallest diagonal entry): indefinite.
    double smallest = p.band[0][0];
    for (int i = 1; i < n; ++i) smallest = std::min(smallest, p.band[i][0]);
    for (int i = 0; i < n; ++i) p.band[i][0] -= 1.01 * smallest;
    CHECK_FALSE(itp::qp::penta::factor(p.band, f, n));
  }
  Penta p = random_spd(10, rng, 1.0);
  double f[40][3];
  p.band[6][1] = std::nan("");
  CHECK_FALSE(itp::qp::penta::factor(p.band, f, 10));
}
