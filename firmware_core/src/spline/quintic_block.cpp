#include "itp/spline/quintic_block.hpp"

namespace itp::spline {
namespace {

// d^k/dτ^k τ^i = falling(i, k) τ^(i-k)
Scalar falling(int i, int k) {
  Scalar f = 1;
  for (int j = 0; j < k; ++j) {  // k <= kMaxDerivative
    f *= static_cast<Scalar>(i - j);
  }
  return f;
}

Scalar power(Scalar x, int n) {
  Scalar p = 1;
  for (int i = 0; i < n; ++i) {  // n <= 11
    p *= x;
  }
  return p;
}

}  // namespace

Matrix6 coefficient_map(Scalar h) {
  // c0..c2 from the start state; c3..c5 solve the end conditions
  // value, first and second derivative at τ = h.
  const Scalar h2 = h * h;
  const Scalar h3 = h2 * h;
  const Scalar h4 = h3 * h;
  const Scalar h5 = h4 * h;
  Matrix6 m = Matrix6::Zero();
  m(0, 0) = 1;
  m(1, 1) = 1;
  m(2, 2) = Scalar(0.5);
  //            p0                         v0                      a0                       p1                       v1                      a1
  m(3, 0) = Scalar(-10) / h3; m(3, 1) = Scalar(-6) / h2; m(3, 2) = Scalar(-1.5) / h; m(3, 3) = Scalar(10) / h3;  m(3, 4) = Scalar(-4) / h2; m(3, 5) = Scalar(0.5) / h;
  m(4, 0) = Scalar(15) / h4;  m(4, 1) = Scalar(8) / h3;  m(4, 2) = Scalar(1.5) / h2; m(4, 3) = Scalar(-15) / h4; m(4, 4) = Scalar(7) / h3;  m(4, 5) = Scalar(-1) / h2;
  m(5, 0) = Scalar(-6) / h5;  m(5, 1) = Scalar(-3) / h4; m(5, 2) = Scalar(-0.5) / h3; m(5, 3) = Scalar(6) / h5;  m(5, 4) = Scalar(-3) / h4; m(5, 5) = Scalar(0.5) / h3;
  return m;
}

Row6 evaluate_row(Scalar h, Scalar tau, int derivative) {
  Row6 e = Row6::Zero();
  for (int i = derivative; i < kBlockStates; ++i) {  // 6 monomials
    e(i) = falling(i, derivative) * power(tau, i - derivative);
  }
  return e * coefficient_map(h);
}

Matrix6 gram(Scalar h, int derivative) {
  Matrix6 g = Matrix6::Zero();
  for (int i = derivative; i < kBlockStates; ++i) {    // 6
    for (int j = derivative; j < kBlockStates; ++j) {  // 6
      const int p = i + j - 2 * derivative + 1;
      g(i, j) = falling(i, derivative) * falling(j, derivative) * power(h, p) / static_cast<Scalar>(p);
    }
  }
  const Matrix6 m = coefficient_map(h);
  return m.transpose() * g * m;
}

Row6 linear_moment(Scalar h, Scalar r0, Scalar r1, int derivative) {
  Row6 e = Row6::Zero();
  for (int i = derivative; i < kBlockStates; ++i) {  // 6
    const int p = i - derivative;  // d^k τ^i = falling(i, k) τ^p
    e(i) = falling(i, derivative) * (r0 * power(h, p + 1) / static_cast<Scalar>(p + 1) +
                                     r1 * power(h, p + 2) / static_cast<Scalar>(p + 2));
  }
  return e * coefficient_map(h);
}

Scalar eval_monomial(const Scalar* c, Scalar tau, int derivative) {
  // falling(i, k) for k = 0..kMaxDerivative: the same exact integers, looked up
  // (the planner evaluates its splines about 5000 times per cycle).
  static constexpr Scalar kFalling[kMaxDerivative + 1][kBlockStates] = {
      {1, 1, 1, 1, 1, 1}, {0, 1, 2, 3, 4, 5}, {0, 0, 2, 6, 12, 20}, {0, 0, 0, 6, 24, 60}};
  Scalar v = 0;
  if (derivative < 0 || derivative > kMaxDerivative) {
    for (int i = kBlockStates - 1; i >= derivative && i >= 0; --i) {  // 6 coefficients
      v = v * tau + falling(i, derivative) * c[i];
    }
    return v;
  }
  const Scalar* f = kFalling[derivative];
  for (int i = kBlockStates - 1; i >= derivative; --i) {  // 6 coefficients
    v = v * tau + f[i] * c[i];
  }
  return v;
}

void block_coefficients(Scalar h, const Scalar* knots, int blocks, Scalar* coefficients) {
  const Matrix6 m = coefficient_map(h);
  for (int b = 0; b < blocks; ++b) {  // blocks <= the caller's capacity
    const Vector6 c = m * Eigen::Map<const Vector6>(knots + 3 * b);
    for (int k = 0; k < kBlockStates; ++k) {  // 6 coefficients
      coefficients[6 * b + k] = c(k);
    }
  }
}

Scalar eval_spline(const Scalar* coefficients, int blocks, Scalar h, Scalar origin, Scalar x, int derivative) {
  Scalar u = (x - origin) / h;
  u = u < 0 ? Scalar(0) : (u > static_cast<Scalar>(blocks) ? static_cast<Scalar>(blocks) : u);
  int b = static_cast<int>(u);
  b = b >= blocks ? blocks - 1 : b;
  return eval_monomial(coefficients + 6 * b, (u - static_cast<Scalar>(b)) * h, derivative);
}

Row6 integral_row(Scalar h, Scalar a, Scalar b) {
  Row6 e;
  for (int i = 0; i < kBlockStates; ++i) {  // 6
    e(i) = (power(b, i + 1) - power(a, i + 1)) / static_cast<Scalar>(i + 1);
  }
  return e * coefficient_map(h);
}

}  // namespace itp::spline
