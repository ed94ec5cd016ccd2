#include "itp/geometry/reference_polyline.hpp"

#include <algorithm>
#include <cmath>

#include "itp/configurations.hpp"
#include "itp/core/assert.hpp"

namespace itp::geometry {

const char* to_string(ReferenceLineStatus status) {
  switch (status) {
    case ReferenceLineStatus::kOk: return "ok";
    case ReferenceLineStatus::kTooFewPoints: return "too_few_points";
    case ReferenceLineStatus::kTooManyPoints: return "too_many_points";
    case ReferenceLineStatus::kNonFinite: return "non_finite";
    case ReferenceLineStatus::kRepeatedPoints: return "repeated_points";
    case ReferenceLineStatus::kSharpTurn: return "sharp_turn";
    case ReferenceLineStatus::kTooShort: return "too_short";
    case ReferenceLineStatus::kFitFailed: return "fit_failed";
  }
  return "unknown";
}

template <class Cfg>
ReferenceLineStatus check_reference_polyline(std::span<const Point2> polyline) {
  const int n = static_cast<int>(polyline.size());
  if (n < 2) {
    return ReferenceLineStatus::kTooFewPoints;
  }
  if (n > Cfg::kMaxReferencePoints) {
    return ReferenceLineStatus::kTooManyPoints;
  }
  for (int i = 0; i < Cfg::kMaxReferencePoints && i < n; ++i) {
    if (!is_finite(polyline[static_cast<std::size_t>(i)])) {
      return ReferenceLineStatus::kNonFinite;
    }
  }
  const Scalar cos_max_turn = std::cos(config::kMaxReferenceTurnPerPoint);
  Scalar length = Scalar(0);
  for (int i = 0; i + 1 < n && i < Cfg::kMaxReferencePoints; ++i) {
    const Point2 d = polyline[static_cast<std::size_t>(i + 1)] - polyline[static_cast<std::size_t>(i)];
    const Scalar len = norm(d);
    if (!(len >= config::kMinReferencePointSpacing)) {
      return ReferenceLineStatus::kRepeatedPoints;
    }
    if (i > 0) {
      const Point2 prev = polyline[static_cast<std::size_t>(i)] - polyline[static_cast<std::size_t>(i - 1)];
      if (dot(prev, d) < cos_max_turn * norm(prev) * len) {
        return ReferenceLineStatus::kSharpTurn;
      }
    }
    length += len;
  }
  if (!std::isfinite(length)) {
    return ReferenceLineStatus::kNonFinite;
  }
  if (length < config::kMinReferenceLineLength) {
    return ReferenceLineStatus::kTooShort;
  }
  return ReferenceLineStatus::kOk;
}

template <class Cfg>
Scalar distance_to_polyline(std::span<const Point2> polyline, Point2 p) {
  const int n = static_cast<int>(polyline.size());
  ITP_EXPECTS(n >= 1 && n <= Cfg::kMaxReferencePoints);
  Scalar best = norm(p - polyline[0]);
  for (int i = 0; i + 1 < n && i < Cfg::kMaxReferencePoints; ++i) {
    const Point2 a = polyline[static_cast<std::size_t>(i)];
    const Point2 d = polyline[static_cast<std::size_t>(i + 1)] - a;
    const Scalar dd = dot(d, d);
    const Scalar tau = dd > Scalar(0) ? std::clamp(dot(p - a, d) / dd, Scalar(0), Scalar(1)) : Scalar(0);
    best = std::min(best, norm(p - (a + tau * d)));
  }
  return best;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                           \
  template ReferenceLineStatus check_reference_polyline<C>(std::span<const Point2>); \
  template Scalar distance_to_polyline<C>(std::span<const Point2>, Point2);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::geometry
