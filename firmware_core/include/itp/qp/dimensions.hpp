#pragma once
// Compile-time shape of one QP class: scalar type and capacities. Every array
// in the problem, workspace and result, and every loop bound of the solver,
// derives from these constants (docs/qp.md, "Memory").
#include <cstdint>
#include <type_traits>

#include "itp/config.hpp"

namespace itp::qp {

// S       scalar type (double or float)
// N       max variables n
// M       max general constraint rows m (each row is two-sided: lbA <= a x <= ubA)
// NnzRow  max nonzeros per constraint row (A is stored row-sparse)
// Bw      Hessian half-bandwidth: H(i, j) == 0 whenever |i - j| > Bw
// Chain   > 0: problems in chain form (chain_form.hpp) with chains of at most
//         this many positions are tried with the chain solver first
//         (chain_qp.hpp); 0: the general active-set solver only
template <typename S, int N, int M, int NnzRow, int Bw, int Chain = 0>
struct QpDims {
  using Scalar = S;
  static constexpr int kMaxChainLength = Chain;
  static constexpr int kMaxVariables = N;
  static constexpr int kMaxRows = M;
  static constexpr int kMaxRowNonzeros = NnzRow;
  static constexpr int kBandwidth = Bw;
  // A's column indices and per-row counts: one byte while every column fits
  // (N <= 255: all of the planner's shapes and qp_solve's), else two. The
  // path QP's 400 x 6 indices take 2.4 KB less RAM.
  using ColumnIndex = std::conditional_t<(N <= 255), std::uint8_t, std::int16_t>;
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
  // From-scratch refactorisations of the working-set factor per solve (an
  // inaccurate optimum, a dual ray that fails its check, cycling).
  static constexpr int kMaxRefactorisations = 2;
  // Consecutive zero-length steps after which even Bland's rule is taken to
  // cycle through rounding: refactorise, then kNumericalTrouble.
  static constexpr int kMaxZeroRun = 4 * (N + 2);
  // Outer proximal-point iterations for a singular H (each one a hotstarted
  // inner solve; all inner iterations count against kMaxIterations).
  static constexpr int kMaxProximalSteps = 2 * (N + M) + 100;

  static_assert(N >= 1 && M >= 0 && NnzRow >= 1 && Bw >= 0 && Chain >= 0 && Chain <= N, "bad QP capacities");
  static_assert(N + M < 32767, "constraint indices are stored as int16");
  static_assert(NnzRow <= N, "a row cannot have more nonzeros than variables");
  static_assert(Bw < N, "half-bandwidth must be below the variable count");
};

// The planner's three QP shapes (docs/qp.md and PLANNER.md), per
// configuration Cfg; rows and variables come from the configuration
// (itp/config.hpp). No default: every user names its configuration (the
// firmware its own, host tools and tests itp::DefaultConfig), so that a
// shape cannot silently fall back to another build's capacities.
// Path QP: (l, l', l'') per knot; quintic Hermite blocks couple knot i with
// i+1, i.e. 6 consecutive variables -> half-bandwidth 5; every row (a
// sample's corridor, l' or l'' bound) touches exactly the 6 variables of
// its block (path/path_optimizer.cpp).
inline constexpr int kPathQpRowNonzeros = 6;
inline constexpr int kPathQpBandwidth = 5;
// Speed QP: (s, s', s'') per knot, rows of one block.
inline constexpr int kSpeedQpRowNonzeros = 6;
inline constexpr int kSpeedQpBandwidth = 5;
// Coarse decision QP: (l_i, t_i) interleaved; second differences couple
// sample i-1..i+1 -> half-bandwidth 4; bounds plus monotone-time rows. Two
// chains of kCoarseSamples positions: solved by the chain solver first.
inline constexpr int kCoarseQpRowNonzeros = 2;
inline constexpr int kCoarseQpBandwidth = 4;

// General structure (issue 15): dense H (half-bandwidth N - 1) and rows with
// up to N nonzeros, i.e. any sparsity, for n <= 160 and m <= 1200. The same
// solver, instantiated on these capacities; the planner never links it (host
// tools only: qp_solve picks it for files that do not fit a banded shape).
// Memory (double): problem 2.1 MB, workspace 0.4 MB, result 12 KB.
template <typename S, int N = 160, int M = 1200>
using GeneralQpDims = QpDims<S, N, M, N, N - 1>;

template <typename S, class Cfg>
using PathQpDims =
    QpDims<S, Cfg::kPathVariables, Cfg::kPathQpRows, kPathQpRowNonzeros, kPathQpBandwidth>;
template <typename S, class Cfg>
using SpeedQpDims =
    QpDims<S, Cfg::kSpeedVariables, Cfg::kSpeedQpRows, kSpeedQpRowNonzeros, kSpeedQpBandwidth>;
template <typename S, class Cfg>
using CoarseQpDims = QpDims<S, Cfg::kCoarseQpVariables, Cfg::kCoarseQpRows, kCoarseQpRowNonzeros,
                            kCoarseQpBandwidth, Cfg::kCoarseSamples>;

}  // namespace itp::qp
