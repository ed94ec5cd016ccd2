#pragma once
// Entry point of the chain solver (chain_solver.hpp) for a QpProblem whose
// dims declare a chain capacity (QpDims' Chain > 0): the coarse decision QP.
// It settles what it can prove, kOptimal (KKT checked) or kInvalidInput, and
// hands everything else to the general active-set solver: a problem not in
// chain form, an infeasible chain, a reduced H that is not positive definite,
// the iteration cap. So kInfeasible, kNotConvex and kNumericalTrouble keep
// the general solver's certificates (solver.hpp).
//
// Memory: the chain's link bounds and the solver state live on the stack
// (~18 arrays of Chain scalars, docs/qp.md); H, g and the bounds are read in place.
#include <cstdint>
#include <type_traits>

#include "itp/qp/chain_form.hpp"
#include "itp/qp/chain_solver.hpp"
#include "itp/qp/problem.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp {

enum class ChainVerdict : std::uint8_t {
  kSettled,           // result.status is final (kOptimal or kInvalidInput)
  kUseGeneralSolver,  // result is scratch: solve with solve_cold / solve_warm / solve_hot
};

namespace chain {

// The warm marks of chain c (stride k) from a working set.
template <class D, int L>
void load_marks(const QpProblem<D>& p, const WorkingSet<D>& warm, int k, int c, ChainSolver<D, L>& solver) {
  const int count = warm.size < D::kMaxActive ? warm.size : D::kMaxActive;
  for (int e = 0; e < count; ++e) {  // <= N + 1 entries
    const ActiveConstraint& a = warm.entries[e];
    if (a.is_bound != 0) {
      if (a.index >= 0 && a.index < p.n && a.index % k == c) solver.mark_bound(a.index / k, a.side);
    } else if (a.index >= 0 && a.index < p.m && p.a_nnz[a.index] == 2) {
      const int j = p.a_col[a.index][0];
      if (j % k == c) solver.mark_link(j / k, a.side);
    }
  }
}

// The final marks per variable j, packed: bits 0-1 its bound, bits 2-3 the
// link from j to j + K (0 none, 1 lower, 2 upper), so that the working set
// is written only after every chain succeeded (the warm start may be the
// very working set of the result, and a fallback restarts from it).
inline std::uint8_t side_code(int side) { return side < 0 ? 1 : 2; }
inline int code_side(int code) { return code == 1 ? -1 : 1; }

// x, multipliers and the packed marks of chain c into the result.
template <class D, int L>
void store(const QpProblem<D>& p, const ChainData<D, L>& ch, const ChainSolver<D, L>& solver, QpResult<D>& res,
           std::uint8_t* marks) {
  using S = typename D::Scalar;
  for (int q = 0; q < ch.n; ++q) {  // < L
    const int j = ch.var(q);
    res.x[j] = solver.x()[q];
    res.y_bounds[j] = solver.bound_multiplier(q);
    const std::int8_t b = solver.bound_mark(q);
    const int b_side = b == kFixed ? (solver.bound_multiplier(q) > S(0) ? 1 : -1) : b;
    marks[j] = b != kInactive ? side_code(b_side) : 0;
    const int r = ch.link_row[q];
    if (r < 0) continue;
    res.y_rows[r] = solver.link_multiplier(q) / p.a_val[r][1];
    if (solver.link_mark(q) != kInactive) marks[j] = static_cast<std::uint8_t>(marks[j] | (side_code(solver.link_mark(q)) << 2));
  }
}

// The working set from the packed marks: bounds, then link rows.
template <class D>
void write_working_set(const QpProblem<D>& p, const std::uint8_t* marks, QpResult<D>& res) {
  res.working_set.clear();
  for (int j = 0; j < p.n; ++j) {  // < N
    if ((marks[j] & 3) != 0) static_cast<void>(res.working_set.push(j, true, code_side(marks[j] & 3)));
  }
  for (int r = 0; r < p.m; ++r) {  // < M: row r links its first column j
    const int code = marks[p.a_col[r][0]] >> 2;
    if (code != 0) static_cast<void>(res.working_set.push(r, false, code_side(code)));
  }
}

}  // namespace chain

// Solves `p` with the chain solver, from `warm`'s working set if given (it
// may be res.working_set itself). When the general solver must take over,
// res.working_set is left as it was.
template <class D>
ChainVerdict solve_chain(const QpProblem<D>& p, const QpSettings<typename D::Scalar>& settings,
                         const std::type_identity_t<WorkingSet<D>>* warm, QpResult<D>& res) {
  using S = typename D::Scalar;
  constexpr int L = D::kMaxChainLength > 0 ? D::kMaxChainLength : 1;
  res.iterations = 0;
  res.refactorisations = 0;
  res.proximal_steps = 0;
  res.certificate_residual = S(0);
  res.certificate_gap = S(0);
  if (!is_valid(p)) {
    res.working_set.clear();
    res.status = QpStatus::kInvalidInput;
    return ChainVerdict::kSettled;
  }
  std::uint8_t marks[static_cast<std::size_t>(D::kMaxVariables)];  // find_stride's scratch, then the marks
  const int k = D::kMaxChainLength > 0 ? chain::find_stride(p, L, marks) : 0;
  if (k == 0) return ChainVerdict::kUseGeneralSolver;
  for (int r = 0; r < p.m; ++r) res.y_rows[r] = S(0);  // < M
  const int cap = (settings.max_iterations > 0 && settings.max_iterations < D::kMaxIterations)
                      ? settings.max_iterations
                      : D::kMaxIterations;
  for (int c = 0; c < k; ++c) {  // <= 2 chains
    chain::ChainData<D, L> ch;
    chain::gather(p, k, c, ch);
    chain::ChainSolver<D, L> solver(ch, settings);
    solver.clear_marks();
    if (warm != nullptr) chain::load_marks(p, *warm, k, c, solver);
    const bool solved = solver.solve(cap - res.iterations, res.iterations);
    res.refactorisations += solver.factorisations();
    if (!solved) return ChainVerdict::kUseGeneralSolver;
    chain::store(p, ch, solver, res, marks);
  }
  chain::write_working_set(p, marks, res);
  S objective = S(0);
  for (int i = 0; i < p.n; ++i) {  // < N: 1/2 x'Hx + g'x over the band
    S hx = p.h_band[i][0] * res.x[i] * S(0.5);
    for (int off = 1; off <= D::kBandwidth && off <= i; ++off) hx += p.h_band[i][off] * res.x[i - off];  // <= Bw
    objective += res.x[i] * (hx + p.g[i]);
  }
  res.objective = objective;
  res.status = QpStatus::kOptimal;
  return ChainVerdict::kSettled;
}

}  // namespace itp::qp
