#pragma once
// Outcome of one QP solve. Errors are values; the solver never throws.
#include <cstdint>

namespace itp::qp {

enum class QpStatus : std::uint8_t {
  kOptimal = 0,         // KKT conditions hold within the tolerances
  kInfeasible = 1,      // primal infeasible (dual unbounded); x is not usable
  kIterationLimit = 2,  // stopped at the iteration cap; x is not usable
  kInvalidInput = 3,    // NaN/Inf data, lb > ub, lbA > ubA, sizes beyond capacity
  kNotConvex = 4,       // Cholesky of H failed: H not positive definite
  kNotFactored = 5,     // hotstart requested without a previous factorisation
};

const char* to_string(QpStatus status);

// True only for kOptimal: every other status leaves x unusable.
constexpr bool is_usable(QpStatus status) { return status == QpStatus::kOptimal; }

}  // namespace itp::qp
