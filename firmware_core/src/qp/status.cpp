#include "itp/qp/status.hpp"

namespace itp::qp {

const char* to_string(QpStatus status) {
  switch (status) {
    case QpStatus::kOptimal: return "optimal";
    case QpStatus::kInfeasible: return "infeasible";
    case QpStatus::kIterationLimit: return "iteration_limit";
    case QpStatus::kInvalidInput: return "invalid_input";
    case QpStatus::kNotConvex: return "not_convex";
    case QpStatus::kNotFactored: return "not_factored";
    case QpStatus::kNumericalTrouble: return "numerical_trouble";
    case QpStatus::kUnbounded: return "unbounded";
  }
  return "unknown";
}

}  // namespace itp::qp
