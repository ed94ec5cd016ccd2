#include "itp/core/status.hpp"

namespace itp {

const char* to_string(PlanStatus status) {
  switch (status) {
    case PlanStatus::kOk: return "ok";
    case PlanStatus::kFallback: return "fallback";
    case PlanStatus::kInvalidInput: return "invalid_input";
  }
  return "unknown";
}

}  // namespace itp
