#pragma once
// Minimum, maximum and clamp on Scalar, written once. Unlike std::min/max the
// comparison is spelled out (a < b ? a : b), so which argument wins on a tie
// or a NaN is fixed here and the same on every target.
#include "itp/config.hpp"

namespace itp {

constexpr Scalar min_of(Scalar a, Scalar b) { return a < b ? a : b; }
constexpr Scalar max_of(Scalar a, Scalar b) { return a > b ? a : b; }
constexpr Scalar clamp(Scalar v, Scalar lo, Scalar hi) { return v < lo ? lo : (v > hi ? hi : v); }

}  // namespace itp
