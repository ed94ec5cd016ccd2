#include <doctest/doctest.h>

#include <array>
#include <random>

#include "itp/spline/quintic_block.hpp"

using namespace itp::spline;
using itp::Scalar;

namespace {

// A random quintic q(τ) = Σ a_k τ^k, the independent reference.
struct Poly {
  std::array<Scalar, 6> a{};
  Scalar d(Scalar t, int k) const {  // k-th derivative
    Scalar v = 0;
    for (int i = k; i < 6; ++i) {
      Scalar f = 1;
      for (int j = 0; j < k; ++j) f *= static_cast<Scalar>(i - j);
      Scalar p = 1;
      for (int j = 0; j < i - k; ++j) p *= t;
      v += a[static_cast<std::size_t>(i)] * f * p;
    }
    return v;
  }
  // ∫_0^h (q^(k))² by expanding the square into monomials.
  Scalar square_integral(Scalar h, int k) const {
    Scalar total = 0;
    for (int i = k; i < 6; ++i) {
      for (int j = k; j < 6; ++j) {
        Scalar fi = 1, fj = 1;
        for (int m = 0; m < k; ++m) {
          fi *= static_cast<Scalar>(i - m);
          fj *= static_cast<Scalar>(j - m);
        }
        const int p = i + j - 2 * k + 1;
        Scalar hp = 1;
        for (int m = 0; m < p; ++m) hp *= h;
        total += a[static_cast<std::size_t>(i)] * a[static_cast<std::size_t>(j)] * fi * fj * hp / p;
      }
    }
    return total;
  }
};

Vector6 knot_states(const Poly& q, Scalar h) {
  Vector6 x;
  x << q.d(0, 0), q.d(0, 1), q.d(0, 2), q.d(h, 0), q.d(h, 1), q.d(h, 2);
  return x;
}

}  // namespace

TEST_CASE("a quintic block reproduces any quintic from its end states") {
  std::mt19937 rng(1);
  std::uniform_real_distribution<Scalar> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    Poly q;
    for (auto& c : q.a) c = u(rng);
    const Scalar h = 0.3 + 10 * (u(rng) + 1);
    for (auto& c : q.a) c /= 1 + h * h;  // keep values moderate over long blocks
    const Vector6 x = knot_states(q, h);
    for (int k = 0; k <= 3; ++k) {
      for (Scalar frac : {0.0, 0.17, 0.5, 0.83, 1.0}) {
        const Scalar t = frac * h;
        const Scalar got = evaluate_row(h, t, k) * x;
        CHECK(got == doctest::Approx(q.d(t, k)).epsilon(1e-9).scale(1.0));
      }
    }
  }
}

TEST_CASE("Gram matrices integrate squared derivatives exactly") {
  std::mt19937 rng(2);
  std::uniform_real_distribution<Scalar> u(-1, 1);
  for (int trial = 0; trial < 100; ++trial) {
    Poly q;
    for (auto& c : q.a) c = u(rng);
    const Scalar h = 0.5 + 4 * (u(rng) + 1);
    const Vector6 x = knot_states(q, h);
    for (int k = 0; k <= 3; ++k) {
      const Scalar got = x.transpose() * gram(h, k) * x;
      const Scalar ref = q.square_integral(h, k);
      CHECK(got == doctest::Approx(ref).epsilon(1e-8));
    }
    // Gram matrices are symmetric positive semidefinite.
    for (int k = 0; k <= 3; ++k) {
      const Matrix6 g = gram(h, k);
      CHECK((g - g.transpose()).norm() <= 1e-9 * (1 + g.norm()));
    }
  }
}

TEST_CASE("the linear moment integrates value times a linear reference") {
  Poly q;
  q.a = {0.3, -0.2, 0.1, 0.05, -0.01, 0.002};
  const Scalar h = 5.0;
  const Vector6 x = knot_states(q, h);
  const Scalar r0 = 1.5;
  const Scalar r1 = -0.25;
  // Midpoint rule with many steps as an independent reference.
  Scalar ref = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const Scalar t = (i + 0.5) * h / n;
    ref += q.d(t, 0) * (r0 + r1 * t) * h / n;
  }
  const Scalar got = linear_moment(h, r0, r1) * x;
  CHECK(got == doctest::Approx(ref).epsilon(1e-7));
  // Same with the first derivative of the value.
  Scalar ref1 = 0;
  for (int i = 0; i < n; ++i) {
    const Scalar t = (i + 0.5) * h / n;
    ref1 += q.d(t, 1) * (r0 + r1 * t) * h / n;
  }
  CHECK(linear_moment(h, r0, r1, 1) * x == doctest::Approx(ref1).epsilon(1e-7));
}

TEST_CASE("the integral row integrates the value over a sub-interval") {
  Poly q;
  q.a = {-0.4, 0.3, -0.05, 0.01, 0.002, -0.0003};
  const Scalar h = 5.0;
  const Vector6 x = knot_states(q, h);
  // Antiderivative of the polynomial, the independent reference.
  auto anti = [&](Scalar t) {
    Scalar v = 0;
    Scalar p = t;
    for (int i = 0; i < 6; ++i) {
      v += q.a[static_cast<std::size_t>(i)] * p / (i + 1);
      p *= t;
    }
    return v;
  };
  for (auto [a, b] : {std::pair<Scalar, Scalar>{0, 5}, {1.25, 3.5}, {2, 2}, {4.9, 5}}) {
    const Scalar got = integral_row(h, a, b) * x;
    CHECK(got == doctest::Approx(anti(b) - anti(a)).epsilon(1e-10).scale(1.0));
  }
}

TEST_CASE("Horner evaluation of the block's coefficients equals the evaluation rows") {
  std::mt19937 rng(9);
  std::uniform_real_distribution<Scalar> u(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    Vector6 x;
    for (int i = 0; i < 6; ++i) x(i) = u(rng);
    const Scalar h = 0.5 + 5 * (u(rng) + 1);
    const Vector6 c = coefficient_map(h) * x;
    for (int k = 0; k <= 3; ++k) {
      for (Scalar frac : {0.0, 0.3, 0.7, 1.0}) {
        const Scalar want = evaluate_row(h, frac * h, k) * x;
        CHECK(eval_monomial(c.data(), frac * h, k) == doctest::Approx(want).epsilon(1e-10).scale(1.0));
      }
    }
  }
}
