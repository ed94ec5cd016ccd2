#pragma once
// Compile-time shape of one QP class: scalar type and capacities. Every array
// in the problem, workspace and result, and every loop bound of the solver,
// derives from these constants (docs/qp.md, "Memory").
#include <cstdint>

#include "itp/config.hpp"

namespace itp::qp {

// S       scalar type (double or float)
// N       max variables n
// M       max general constraint rows m (each row is two-sided: lbA <= a x <= ubA)
// NnzRow  max nonzeros per constraint row (A is stored row-sparse)
// Bw      Hessian half-bandwidth: H(i, j) == 0 whenever |i - j| > Bw
template <typename S, int N, int M, int NnzRow, int Bw>
struct QpDims {
  using Scalar = S;
  static constexpr int kMaxVariables = N;
  static constexpr int kMaxRows = M;
  static constexpr int kMaxRowNonzeros = NnzRow;
  static constexpr int kBandwidth = Bw;
  // Constraint index space used internally: bounds 0..N-1, rows N..N+M-1.
  static constexpr int kMaxConstraints = N + M;
  // The working set never holds more than N linearly independent constraints
  // (plus one dependent candidate, transiently, while its step is computed).
  static constexpr int kMaxActive = N + 1;
  // Hard cap of add/remove iterations. Each constraint can enter and leave the
  // working set a bounded number of times in practice; 3(N+M) leaves ample
  // margin (a solve of the path QP needs ~20-60). The run-time setting may
  // only lower it.
  static constexpr int kMaxIterations = 3 * (N + M);
  // Consecutive zero-length dual steps tolerated before Bland's rule is used.
  static constexpr int kMaxZeroSteps = N + 2;
  // From-scratch refactorisations of the working-set factor per solve.
  static constexpr int kMaxRefactorisations = 2;

  static_assert(N >= 1 && M >= 0 && NnzRow >= 1 && Bw >= 0, "bad QP capacities");
  static_assert(N + M < 32767, "constraint indices are stored as int16");
  static_assert(NnzRow <= N, "a row cannot have more nonzeros than variables");
  static_assert(Bw < N, "half-bandwidth must be below the variable count");
};

// The planner's three QP shapes (docs/qp.md and PLANNER.md).
// Path QP: (l, l', l'') at 21 knots; quintic Hermite blocks couple knot i with
// i+1, i.e. 6 consecutive variables -> half-bandwidth 5. Rows: 10 corridor +
// 5 curvature samples per block, each touching the 6 variables of its block.
inline constexpr int kPathQpRows = 400;
inline constexpr int kPathQpRowNonzeros = 9;
inline constexpr int kPathQpBandwidth = 5;
// Speed QP: (s, s', s'') at 15 knots, 15 rows per ST block.
inline constexpr int kSpeedQpRows = 210;
inline constexpr int kSpeedQpRowNonzeros = 6;
inline constexpr int kSpeedQpBandwidth = 5;
// Coarse decision QP: (l_i, t_i) interleaved at 20 samples; second differences
// couple sample i-1..i+1 -> half-bandwidth 4; bounds plus monotone-time rows.
inline constexpr int kCoarseQpVariables = 2 * config::kCoarseSamples;
inline constexpr int kCoarseQpRows = config::kCoarseSamples;
inline constexpr int kCoarseQpRowNonzeros = 2;
inline constexpr int kCoarseQpBandwidth = 4;

template <typename S>
using PathQpDims = QpDims<S, config::kPathVariables, kPathQpRows, kPathQpRowNonzeros,
                          kPathQpBandwidth>;
template <typename S>
using SpeedQpDims = QpDims<S, config::kSpeedVariables, kSpeedQpRows,
                           kSpeedQpRowNonzeros, kSpeedQpBandwidth>;
template <typename S>
using CoarseQpDims = QpDims<S, kCoarseQpVariables, kCoarseQpRows, kCoarseQpRowNonzeros,
                            kCoarseQpBandwidth>;

}  // namespace itp::qp
