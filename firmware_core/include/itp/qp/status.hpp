#pragma once
// Outcome of one QP solve. Errors are values; the solver never throws.
#include <cstdint>

namespace itp::qp {

// Values are sent over the link (docs/protocol.md, QpSolve reply): append
// new ones, never renumber.
enum class QpStatus : std::uint8_t {
  kOptimal = 0,         // KKT conditions hold within the tolerances; x checked feasible and finite
  kInfeasible = 1,      // primal infeasible: a dual ray was found AND checked (result holds it)
  kIterationLimit = 2,  // stopped at the iteration cap; x is not usable
  kInvalidInput = 3,    // NaN/Inf data, lb > ub, lbA > ubA, sizes beyond capacity
  kNotConvex = 4,       // H has a negative eigenvalue: a direction v with v'Hv < 0 was found
  kNotFactored = 5,     // hotstart requested without a previous factorisation
  // The arithmetic failed, not the problem: a working set that stays rank
  // deficient after refactorising, a dual ray whose check fails, cycling, a
  // non-finite iterate, or an x that fails the final feasibility check.
  // Never reported as kInfeasible or kOptimal (docs/qp.md, "Statuses").
  kNumericalTrouble = 6,
  // Dual infeasible (only possible with a singular H): the objective falls
  // without bound along a direction d with Hd = 0 that every constraint allows.
  kUnbounded = 7,
};

const char* to_string(QpStatus status);

// True only for kOptimal: every other status leaves x unusable.
constexpr bool is_usable(QpStatus status) { return status == QpStatus::kOptimal; }

}  // namespace itp::qp
