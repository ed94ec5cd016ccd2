#pragma once
// Checks on a raw reference polyline, shared by ReferenceLine::build and the
// scene validator (which must reject a bad line without fitting it).
#include <cstdint>
#include <span>

#include "itp/config.hpp"
#include "itp/geometry/point.hpp"

namespace itp::geometry {

enum class ReferenceLineStatus : std::uint8_t {
  kOk = 0,
  kTooFewPoints,    // fewer than 2 points
  kTooManyPoints,   // more than the configuration's kMaxReferencePoints
  kNonFinite,       // a coordinate is NaN or infinite
  kRepeatedPoints,  // two consecutive points closer than kMinReferencePointSpacing
  kSharpTurn,       // consecutive segments turn by more than kMaxReferenceTurnPerPoint
                    // (a reversal or a kink no road has)
  kTooShort,        // polyline shorter than kMinReferenceLineLength
  kFitFailed,       // the spline system was not positive definite (degenerate knots)
};

const char* to_string(ReferenceLineStatus status);

// Checks count (at most Cfg::kMaxReferencePoints), finiteness, spacing,
// turning and length of `polyline` [m].
template <class Cfg>
ReferenceLineStatus check_reference_polyline(std::span<const Point2> polyline);

// Distance [m] from `p` to the nearest point of the polyline (segments
// included). Requires a non-empty polyline of at most Cfg::kMaxReferencePoints.
template <class Cfg>
Scalar distance_to_polyline(std::span<const Point2> polyline, Point2 p);

}  // namespace itp::geometry
