#include "itp/scene/validation.hpp"

#include <cmath>
#include <initializer_list>

#include "itp/configurations.hpp"
#include "itp/geometry/reference_polyline.hpp"

namespace itp::scene {
namespace {

using R = ValidationReason;

ValidationResult fail(R reason, int index = -1, int sub_index = -1) {
  return {reason, static_cast<std::int16_t>(index), static_cast<std::int16_t>(sub_index)};
}

bool all_finite(std::initializer_list<Scalar> values) {
  for (const Scalar v : values) {  // bounded by the list's length
    if (!std::isfinite(v)) {
      return false;
    }
  }
  return true;
}

bool coordinate_ok(Scalar x, Scalar y) {
  return std::fabs(x) <= config::kMaxCoordinate && std::fabs(y) <= config::kMaxCoordinate;
}

bool size_ok(Scalar size) { return size >= config::kMinObjectSize && size <= config::kMaxObjectSize; }

bool heading_ok(Scalar heading) { return std::fabs(heading) <= config::kMaxAbsoluteHeading; }

// The window prediction times must fall in: around `now` when it is known,
// else anywhere a scene clock can be.
struct TimeWindow {
  Scalar lo;  // [s]
  Scalar hi;  // [s]
};

template <class Cfg>
ValidationResult check_reference_line(const BasicScene<Cfg>& scene) {
  const auto& ref = scene.reference_line;
  for (int i = 0; i < Cfg::kMaxReferencePoints && i < static_cast<int>(ref.size()); ++i) {
    const Point2 p = ref[static_cast<std::size_t>(i)];
    if (!geometry::is_finite(p)) {
      return fail(R::kNonFiniteValue, i);
    }
    if (!coordinate_ok(p.x, p.y)) {
      return fail(R::kCoordinateOutOfRange, i);
    }
  }
  switch (geometry::check_reference_polyline<Cfg>(ref.span())) {
    case geometry::ReferenceLineStatus::kOk: return {};
    case geometry::ReferenceLineStatus::kTooFewPoints: return fail(R::kTooFewReferencePoints);
    case geometry::ReferenceLineStatus::kTooManyPoints: return fail(R::kTooManyReferencePoints);
    case geometry::ReferenceLineStatus::kNonFinite: return fail(R::kNonFiniteValue);
    case geometry::ReferenceLineStatus::kRepeatedPoints: return fail(R::kRepeatedReferencePoints);
    case geometry::ReferenceLineStatus::kSharpTurn: return fail(R::kReferenceLineSharpTurn);
    case geometry::ReferenceLineStatus::kTooShort: return fail(R::kReferenceLineTooShort);
    case geometry::ReferenceLineStatus::kFitFailed: return fail(R::kRepeatedReferencePoints);
  }
  return fail(R::kReferenceLineSharpTurn);
}

template <class Cfg>
ValidationResult check_boundary(const BasicBoundary<Cfg>& b, int which) {
  if (!std::isfinite(b.offset)) {
    return fail(R::kNonFiniteValue, which);
  }
  if (std::fabs(b.offset) > config::kMaxBoundaryOffset) {
    return fail(R::kBoundaryOutOfRange, which);
  }
  const int n = static_cast<int>(b.table.size());
  for (int i = 0; i < Cfg::kMaxBoundaryPoints && i < n; ++i) {
    const BoundaryPoint p = b.table[static_cast<std::size_t>(i)];
    if (!all_finite({p.s, p.l})) {
      return fail(R::kNonFiniteValue, which, i);
    }
    if (std::fabs(p.l) > config::kMaxBoundaryOffset) {
      return fail(R::kBoundaryOutOfRange, which, i);
    }
    if (i > 0 && !(p.s > b.table[static_cast<std::size_t>(i - 1)].s)) {
      return fail(R::kBoundaryTableNotAscending, which, i);
    }
  }
  return {};
}

template <class Cfg>
ValidationResult check_road(const BasicRoad<Cfg>& road) {
  if (!all_finite({road.lane_width, road.target_lane_offset, road.speed_limit})) {
    return fail(R::kNonFiniteValue);
  }
  if (const ValidationResult r = check_boundary(road.left, 0); !r.ok()) {
    return r;
  }
  if (const ValidationResult r = check_boundary(road.right, 1); !r.ok()) {
    return r;
  }
  if (!(road.lane_width >= config::kMinLaneWidth && road.lane_width <= config::kMaxLaneWidth)) {
    return fail(R::kLaneWidthOutOfRange);
  }
  // left - right is piecewise linear with kinks only at the tables' knots,
  // so checking s = 0 and every knot checks every s.
  if (!(road.left.at(Scalar(0)) > road.right.at(Scalar(0)))) {
    return fail(R::kBoundariesCrossed);
  }
  for (const BasicBoundary<Cfg>* b : {&road.left, &road.right}) {  // 2 boundaries
    for (int i = 0; i < Cfg::kMaxBoundaryPoints && i < static_cast<int>(b->table.size()); ++i) {
      const Scalar s = b->table[static_cast<std::size_t>(i)].s;
      if (!(road.left.at(s) > road.right.at(s))) {
        return fail(R::kBoundariesCrossed, b == &road.left ? 0 : 1, i);
      }
    }
  }
  if (std::fabs(road.target_lane_offset) > config::kMaxBoundaryOffset) {
    return fail(R::kTargetLaneOffsetOutOfRange);
  }
  if (!(road.speed_limit >= config::kMinSpeedLimit && road.speed_limit <= config::kMaxAbsoluteSpeed)) {
    return fail(R::kSpeedLimitOutOfRange);
  }
  return {};
}

template <class Cfg>
ValidationResult check_ego(const BasicScene<Cfg>& scene) {
  const EgoState& s = scene.ego.state;
  const VehicleGeometry& g = scene.ego.geometry;
  const VehicleLimits& lim = scene.ego.limits;
  if (!all_finite({s.x, s.y, s.heading, s.v, s.a, s.kappa, g.length, g.width, g.wheelbase,
                   lim.a_min, lim.a_max, lim.lat_acc_max, lim.kappa_max})) {
    return fail(R::kNonFiniteValue);
  }
  if (!coordinate_ok(s.x, s.y)) {
    return fail(R::kCoordinateOutOfRange);
  }
  if (!heading_ok(s.heading)) {
    return fail(R::kHeadingOutOfRange);
  }
  if (!(s.v >= Scalar(0) && s.v <= config::kMaxAbsoluteSpeed)) {
    return fail(R::kEgoSpeedOutOfRange);
  }
  if (std::fabs(s.a) > config::kMaxAbsoluteAcceleration) {
    return fail(R::kEgoAccelerationOutOfRange);
  }
  if (std::fabs(s.kappa) > config::kMaxAbsoluteCurvature) {
    return fail(R::kEgoCurvatureOutOfRange);
  }
  if (!size_ok(g.length) || !size_ok(g.width) || !(g.wheelbase >= config::kMinObjectSize) ||
      !(g.wheelbase < g.length)) {
    return fail(R::kEgoGeometryOutOfRange);
  }
  const Scalar a_lo = config::kMinLimitAcceleration;
  const Scalar a_hi = config::kMaxAbsoluteAcceleration;
  if (!(lim.a_min <= -a_lo && lim.a_min >= -a_hi && lim.a_max >= a_lo && lim.a_max <= a_hi &&
        lim.lat_acc_max >= a_lo && lim.lat_acc_max <= a_hi && lim.kappa_max >= config::kMinLimitCurvature &&
        lim.kappa_max <= config::kMaxAbsoluteCurvature)) {
    return fail(R::kEgoLimitsOutOfRange);
  }
  if (geometry::distance_to_polyline<Cfg>(scene.reference_line.span(), {s.x, s.y}) >
      config::kMaxEgoOffsetFromReference) {
    return fail(R::kEgoFarFromReferenceLine);
  }
  return {};
}

template <class Cfg>
ValidationResult check_static(const BasicScene<Cfg>& scene) {
  const auto& obs = scene.static_obstacles;
  for (int i = 0; i < Cfg::kMaxStaticObstacles && i < static_cast<int>(obs.size()); ++i) {
    const StaticObstacle& o = obs[static_cast<std::size_t>(i)];
    if (!all_finite({o.x, o.y, o.heading, o.length, o.width})) {
      return fail(R::kNonFiniteValue, i);
    }
    if (!coordinate_ok(o.x, o.y)) {
      return fail(R::kCoordinateOutOfRange, i);
    }
    if (!heading_ok(o.heading)) {
      return fail(R::kHeadingOutOfRange, i);
    }
    if (!size_ok(o.length) || !size_ok(o.width)) {
      return fail(R::kObstacleSizeOutOfRange, i);
    }
  }
  return {};
}

template <class Cfg>
ValidationResult check_dynamic(const BasicScene<Cfg>& scene, TimeWindow window) {
  const auto& obs = scene.dynamic_obstacles;
  for (int i = 0; i < Cfg::kMaxDynamicObstacles && i < static_cast<int>(obs.size()); ++i) {
    const BasicDynamicObstacle<Cfg>& o = obs[static_cast<std::size_t>(i)];
    if (!all_finite({o.length, o.width})) {
      return fail(R::kNonFiniteValue, i);
    }
    if (!size_ok(o.length) || !size_ok(o.width)) {
      return fail(R::kObstacleSizeOutOfRange, i);
    }
    if (o.trajectory.empty()) {
      return fail(R::kEmptyTrajectory, i);
    }
    const int n = static_cast<int>(o.trajectory.size());
    for (int k = 0; k < Cfg::kMaxPredictionSamples && k < n; ++k) {
      const TimedPose& p = o.trajectory[static_cast<std::size_t>(k)];
      if (!all_finite({p.t, p.x, p.y, p.heading, p.v})) {
        return fail(R::kNonFiniteValue, i, k);
      }
      if (!coordinate_ok(p.x, p.y)) {
        return fail(R::kCoordinateOutOfRange, i, k);
      }
      if (!heading_ok(p.heading)) {
        return fail(R::kHeadingOutOfRange, i, k);
      }
      if (!(p.t >= window.lo && p.t <= window.hi)) {
        return fail(R::kPredictionTimeOutOfRange, i, k);
      }
      if (k > 0 && !(p.t > o.trajectory[static_cast<std::size_t>(k - 1)].t)) {
        return fail(R::kPredictionTimesNotIncreasing, i, k);
      }
      if (std::fabs(p.v) > config::kMaxAbsoluteSpeed) {
        return fail(R::kObstacleSpeedOutOfRange, i, k);
      }
    }
  }
  return {};
}

// Ids must be unique over static and dynamic obstacles (decisions name them).
template <class Cfg>
ValidationResult check_ids(const BasicScene<Cfg>& scene) {
  constexpr int kMax = Cfg::kMaxObstacles;
  std::int32_t ids[std::size_t{kMax}] = {};
  int count = 0;
  for (const StaticObstacle& o : scene.static_obstacles) {  // <= kMaxStaticObstacles
    ids[count++] = o.id;
  }
  for (const BasicDynamicObstacle<Cfg>& o : scene.dynamic_obstacles) {  // <= kMaxDynamicObstacles
    ids[count++] = o.id;
  }
  for (int i = 0; i < kMax && i < count; ++i) {
    for (int j = 0; j < i; ++j) {  // j < i < kMax
      if (ids[i] == ids[j]) {
        return fail(R::kDuplicateObstacleId, i);
      }
    }
  }
  return {};
}

template <class Cfg>
ValidationResult validate_in(const BasicScene<Cfg>& scene, TimeWindow window) {
  if (const ValidationResult r = check_reference_line(scene); !r.ok()) return r;
  if (const ValidationResult r = check_road(scene.road); !r.ok()) return r;
  if (const ValidationResult r = check_ego(scene); !r.ok()) return r;
  if (const ValidationResult r = check_static(scene); !r.ok()) return r;
  if (const ValidationResult r = check_dynamic(scene, window); !r.ok()) return r;
  return check_ids(scene);
}

}  // namespace

template <class Cfg>
ValidationResult validate(const BasicScene<Cfg>& scene, Scalar now) {
  if (!std::isfinite(now) || !(now >= Scalar(0) && now <= config::kMaxSceneTime)) {
    return fail(R::kSceneTimeOutOfRange);
  }
  return validate_in(scene, TimeWindow{now - config::kMaxPredictionTime, now + config::kMaxPredictionTime});
}

template <class Cfg>
ValidationResult validate(const BasicScene<Cfg>& scene) {
  return validate_in(scene, TimeWindow{-config::kMaxPredictionTime, config::kMaxSceneTime + config::kMaxPredictionTime});
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                              \
  template ValidationResult validate<C>(const BasicScene<C>&, Scalar); \
  template ValidationResult validate<C>(const BasicScene<C>&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::scene
