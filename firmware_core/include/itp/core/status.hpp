#pragma once
// Errors are values. Each layer has its own enum class; none of them throws.
#include <cstdint>

namespace itp {

// Outcome of one planning cycle (plan/1 "status").
enum class PlanStatus : std::uint8_t {
  kOk = 0,
  kFallback = 1,      // a safe stopping trajectory was returned; see the reason
  kInvalidInput = 2,  // the scene was rejected; a safe stop was returned
};

const char* to_string(PlanStatus status);

}  // namespace itp
