#pragma once
// One budget for work of different kinds. Each unit of work (a QP's setup,
// one of its iterations) costs its worst measured cost on the target, and
// work is granted only while the sum stays within the budget:
//
//   sum_k  setup_k * solves_k + per_iteration_k * iterations_k  <=  budget
//
// so the cycle's cost of those stages is bounded by the budget, whatever mix
// of stages spends it (docs/performance.md, "Worst case"). Integers: the
// bound is exact, and the same on every target and Scalar type.
#include <cstdint>

namespace itp {

class WorkLedger {
 public:
  // A new cycle with `budget` units to spend.
  void begin(std::int32_t budget) { left_ = budget; }

  // Iterations a solve that costs `setup` plus `per_iteration` each may take
  // within what is left: at most `cap`, 0 when not even one iteration fits.
  int grant(std::int32_t setup, std::int32_t per_iteration, int cap) const {
    const std::int32_t room = left_ - setup;
    if (cap <= 0 || per_iteration <= 0 || room < per_iteration) {
      return 0;
    }
    const std::int32_t fit = room / per_iteration;
    return fit < cap ? static_cast<int>(fit) : cap;
  }
  // Books a solve that took `iterations` (at most what grant() gave).
  void charge(std::int32_t setup, std::int32_t per_iteration, int iterations) {
    left_ -= setup + per_iteration * static_cast<std::int32_t>(iterations);
  }
  std::int32_t left() const { return left_; }

 private:
  std::int32_t left_ = 0;
};

}  // namespace itp
