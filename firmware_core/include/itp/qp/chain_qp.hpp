#pragma once
// Entry point of the chain solver (chain_solver.hpp) for a QpProblem whose
// dims declare a chain capacity (QpDims' Chain > 0): the coarse decision QP.
// It settles what it can prove, kOptimal (KKT checked) or kInvalidInput, and
// hands everything else to the general active-set solver
// (solve_structured below): a problem not in
// chain form, an infeasible chain, a reduced H that is not positive definite,
// the iteration cap. So kInfeasible, kNotConvex and kNumericalTrouble keep
// the general solver's certificates (solver.hpp).
//
// Memory: one chain's copy of H and the links (ChainData) and the solver
// state live on the stack (~20 arrays of Chain scalars, docs/qp.md); its
// g, lb and ub in three rows of the workspace's M_W, idle during a chain solve.
#include <cstdint>

#include "itp/qp/chain_form.hpp"
#include "itp/qp/chain_solver.hpp"
#include "itp/qp/problem.hpp"
#include "itp/qp/solver.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp {

enum class ChainVerdict : std::uint8_t {
  kSettled,           // result.status is final (kOptimal or kInvalidInput)
  kUseGeneralSolver,  // result is scratch: the general solver must solve it (solve_structured does)
};

namespace chain {

// The final marks per variable j, packed: bits 0-1 its bound, bits 2-3 the
// link from j to j + K (0 none, 1 lower, 2 upper), so that the working set
// is written only after every chain succeeded (one byte per variable on the
// stack instead of a second WorkingSet).
inline std::uint8_t side_code(int side) { return side < 0 ? 1 : 2; }
inline int code_side(int code) { return code == 1 ? -1 : 1; }

// Chain c's share of a working set (a warm start's guess): its bounds, and
// its link rows (row r links a_col[r][0] = c + q K to the next position).
template <class D, int L>
void guess(const QpProblem<D>& p, const WorkingSet<D>& start, int k, int c, ChainSolver<D, L>& solver) {
  for (int i = 0; i < start.size && i < D::kMaxActive; ++i) {  // < N + 1
    const ActiveConstraint& e = start.entries[i];
    const int j = e.is_bound != 0 ? e.index : (e.index >= 0 && e.index < p.m ? p.a_col[e.index][0] : -1);
    if (j < 0 || j >= p.n || chain_of(j, k) != c) continue;
    const std::int8_t side = e.side < 0 ? kLower : kUpper;
    if (e.is_bound != 0) {
      solver.guess_bound(position_of(j, k), side);
    } else {
      solver.guess_link(position_of(j, k), side);
    }
  }
}

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

// A solve of `p` with the chain solver: cold, or from the working set `start`
// (a warm start: its constraints are the first guess of the active set).
// `same_matrices`: H and A are those of the last solve with `ws`, which the
// chain solver settled (a hot start: their checks and the chain shape are
// skipped, as the general solver's hotstart skips its factorisation; ignored
// unless ws.chain_stride says so, for the same n and m). Once the problem is
// in chain form, `ws` holds no factor (its rows of M_W lend the chains their
// storage).
template <class D>
ChainVerdict solve_chain(const QpProblem<D>& p, QpWorkspace<D>& ws, const QpSettings<typename D::Scalar>& settings,
                         QpResult<D>& res, const WorkingSet<D>* start = nullptr, bool same_matrices = false) {
  using S = typename D::Scalar;
  constexpr int L = D::kMaxChainLength > 0 ? D::kMaxChainLength : 1;
  res.iterations = 0;
  res.refactorisations = 0;
  res.proximal_steps = 0;
  res.certificate_residual = S(0);
  res.certificate_gap = S(0);
  const int held_stride = ws.chain_stride;
  const bool hot = same_matrices && held_stride > 0 && ws.factored_n == p.n && ws.factored_m == p.m;
  ws.chain_stride = 0;
  // is_valid(p) in parts: the vectors here, A and H off the chains in
  // find_stride (a problem not in chain form goes to the general solver,
  // which checks it all), H on the chains in gather (a hot start skips
  // find_stride, as H and A are those of a settled solve).
  const auto invalid = [&res]() {
    res.working_set.clear();
    res.status = QpStatus::kInvalidInput;
    return ChainVerdict::kSettled;
  };
  if (!is_valid_vectors(p)) return invalid();
  std::uint8_t marks[static_cast<std::size_t>(D::kMaxVariables)];  // find_stride's scratch, then the marks
  const int k = hot ? held_stride : (D::kMaxChainLength > 0 ? chain::find_stride(p, L, marks) : 0);
  if (k == 0) return ChainVerdict::kUseGeneralSolver;
  for (int r = 0; r < p.m; ++r) res.y_rows[r] = S(0);  // < M
  res.objective = S(0);
  const int cap = (settings.max_iterations > 0 && settings.max_iterations < D::kMaxIterations)
                      ? settings.max_iterations
                      : D::kMaxIterations;
  // The chains' g, lb and ub are copied into rows of M_W: the workspace holds
  // no factor from here on (kUseGeneralSolver: the general solver factors H
  // again in any case).
  static_assert(L <= D::kMaxVariables && D::kMaxActive >= 3, "three rows of M_W hold a chain's vectors");
  ws.factored = false;
  for (int c = 0; c < k; ++c) {  // <= 2 chains
    chain::ChainData<D, L> ch;
    if (!chain::gather(p, k, c, ch, ws.m_rows[0], ws.m_rows[1], ws.m_rows[2])) return invalid();
    chain::ChainSolver<D, L> solver(ch, settings);
    if (start != nullptr) chain::guess(p, *start, k, c, solver);
    const bool solved = solver.solve(cap - res.iterations, res.iterations, start != nullptr);
    res.refactorisations += solver.factorisations();
    if (!solved) return ChainVerdict::kUseGeneralSolver;
    chain::store(p, ch, solver, res, marks);
    res.objective += solver.objective();
  }
  chain::write_working_set(p, marks, res);
  res.status = QpStatus::kOptimal;
  ws.chain_stride = k;
  ws.factored_n = p.n;
  ws.factored_m = p.m;
  return ChainVerdict::kSettled;
}

// A solve that uses the chain solver where D allows it (Chain > 0), cold
// (`start` null) or from the working set `start` (and with `same_matrices`,
// see solve_chain, hot): what it cannot settle goes
// to the general solver (solve_cold, or solve_warm from `start`) with what is
// left of the iteration cap, and the result counts both solvers' iterations.
// Without a chain capacity, the general solver alone.
template <class D>
QpStatus solve_structured(const QpProblem<D>& p, QpWorkspace<D>& ws, const QpSettings<typename D::Scalar>& settings,
                          const WorkingSet<D>* start, QpResult<D>& res, bool same_matrices = false) {
  int used = 0;
  QpSettings<typename D::Scalar> rest = settings;
  if constexpr (D::kMaxChainLength > 0) {
    if (solve_chain(p, ws, settings, res, start, same_matrices) == ChainVerdict::kSettled) return res.status;
    used = res.iterations;
    const int cap = settings.max_iterations > 0 ? settings.max_iterations : D::kMaxIterations;
    if (used >= cap) {
      res.status = QpStatus::kIterationLimit;
      return res.status;
    }
    rest.max_iterations = cap - used;
  }
  const QpStatus st = start != nullptr ? solve_warm(p, ws, rest, *start, res) : solve_cold(p, ws, rest, res);
  res.iterations += used;
  return res.status = st;
}

// The cold start of solve_structured.
template <class D>
QpStatus solve_cold_structured(const QpProblem<D>& p, QpWorkspace<D>& ws,
                               const QpSettings<typename D::Scalar>& settings, QpResult<D>& res) {
  return solve_structured(p, ws, settings, static_cast<const WorkingSet<D>*>(nullptr), res);
}

}  // namespace itp::qp
