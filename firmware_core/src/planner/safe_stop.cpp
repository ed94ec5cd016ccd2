#include "itp/planner/safe_stop.hpp"

#include <cmath>

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"
#include "itp/planner/collision_check.hpp"

namespace itp::planner {
namespace {

// A fallback brakes along the last ok plan while that plan is this young and
// the ego still on it (its nearest sample this close): the plan's path is
// collision-checked and continuous with where the ego goes; switching to the
// reference line puts a kink in the path the vehicle then has to steer.
constexpr Scalar kFallbackPathAge = Scalar(3);        // [s]
constexpr Scalar kFallbackPathDistance = Scalar(1);  // [m]

bool finite_state(const scene::EgoState& e) {
  return std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.heading) && std::isfinite(e.v);
}

// The pose at arc length `target` along a trajectory (its samples' s),
// linear between samples, straight on along the last heading beyond its end.
template <class Cfg>
void pose_along(const BasicPlan<Cfg>& path, Scalar target, TrajectoryPoint& p) {
  const TrajectoryPoint* a = &path.trajectory[0];
  const TrajectoryPoint* b = &path.trajectory[0];
  for (std::size_t i = 1; i < path.trajectory.size(); ++i) {  // kTrajectorySamples
    b = &path.trajectory[i];
    if (b->s >= target) {
      break;
    }
    a = b;
  }
  const Scalar span = b->s - a->s;
  const Scalar u = span > Scalar(1e-6) ? clamp((target - a->s) / span, Scalar(0), Scalar(1)) : Scalar(0);
  const Scalar extra = target > b->s ? target - b->s : Scalar(0);
  p.x = a->x + u * (b->x - a->x) + extra * std::cos(b->heading);
  p.y = a->y + u * (b->y - a->y) + extra * std::sin(b->heading);
  p.heading = a->heading + u * (b->heading - a->heading);
  p.kappa = a->kappa;
  p.s = target;
  p.l = a->l + u * (b->l - a->l);
}

// s of the trajectory sample nearest to (x, y); `distance2` its squared distance.
template <class Cfg>
Scalar nearest_sample_s(const BasicPlan<Cfg>& path, Scalar x, Scalar y, Scalar& distance2) {
  Scalar s_begin = 0;
  Scalar best = -1;
  for (const TrajectoryPoint& q : path.trajectory) {  // kTrajectorySamples
    const Scalar dx = q.x - x;
    const Scalar dy = q.y - y;
    const Scalar d2 = dx * dx + dy * dy;
    if (best < 0 || d2 < best) {
      best = d2;
      s_begin = q.s;
    }
  }
  distance2 = best;
  return s_begin;
}

// Largest v^2 |kappa| over a trajectory [m/s^2].
template <class Cfg>
Scalar max_lateral_acceleration(const BasicPlan<Cfg>& plan) {
  Scalar worst = 0;
  for (const TrajectoryPoint& p : plan.trajectory) {  // kTrajectorySamples
    worst = max_of(worst, p.v * p.v * std::fabs(p.kappa));
  }
  return worst;
}

// The previous plan's sample at time `age` after its start (linear between
// samples; its last sample beyond its end).
template <class Cfg>
TrajectoryPoint sample_at_time(const BasicPlan<Cfg>& path, Scalar age) {
  const TrajectoryPoint* a = &path.trajectory[0];
  const TrajectoryPoint* b = &path.trajectory[0];
  for (std::size_t i = 1; i < path.trajectory.size(); ++i) {  // kTrajectorySamples
    b = &path.trajectory[i];
    if (b->t >= age) {
      break;
    }
    a = b;
  }
  const Scalar span = b->t - a->t;
  const Scalar u = span > Scalar(1e-6) ? clamp((age - a->t) / span, Scalar(0), Scalar(1)) : Scalar(1);
  TrajectoryPoint p = *a;
  p.s = a->s + u * (b->s - a->s);
  p.v = a->v + u * (b->v - a->v);
  p.x = a->x + u * (b->x - a->x);
  p.y = a->y + u * (b->y - a->y);
  p.heading = a->heading + u * (b->heading - a->heading);
  return p;
}

// The stop of an invalid scene uses nothing of that scene (issue 13, defect
// 2: a reply never repeats unvalidated input). It starts from the last valid
// state: the last ok plan at this time, braking along it, when that plan is
// recent and `now` is a time; otherwise it is a standstill (v = 0, a = 0) at
// the last valid position (where the last ok plan ends, clamped to its time;
// the origin without one).
template <class Cfg>
void stop_from_last_valid_state(const BasicSafeStopInput<Cfg>& in, Scalar comfort_decel, BasicPlan<Cfg>& out) {
  constexpr int kSamples = Cfg::kTrajectorySamples;
  constexpr Scalar kDt = Cfg::kSpeedHorizon / static_cast<Scalar>(Cfg::kSpeedSamples);
  const bool have_previous = in.previous != nullptr && in.previous->trajectory.size() > 1;
  const Scalar age = in.now - in.previous_time;
  const bool recent = have_previous && age >= 0 && age < kFallbackPathAge;  // false for a NaN time
  TrajectoryPoint start{};
  if (have_previous) {
    const Scalar end_t = in.previous->trajectory[in.previous->trajectory.size() - 1].t;
    start = sample_at_time(*in.previous, recent ? age : end_t);
  }
  const Scalar v0 = recent ? max_of(start.v, Scalar(0)) : Scalar(0);
  for (int k = 0; k < kSamples; ++k) {  // kTrajectorySamples
    const Scalar t = kDt * static_cast<Scalar>(k);
    const Scalar t_stop = v0 / -comfort_decel;
    const Scalar tt = min_of(t, t_stop);
    const Scalar d = v0 * tt + Scalar(0.5) * comfort_decel * tt * tt;
    TrajectoryPoint p = start;
    p.t = t;
    p.v = max_of(v0 + comfort_decel * t, Scalar(0));
    p.a = t < t_stop ? comfort_decel : Scalar(0);
    if (recent) {
      pose_along(*in.previous, start.s + d, p);
    }
    // The caller cleared it; kSamples = kTrajectorySamples = capacity.
    static_cast<void>(out.trajectory.push_back(p));
  }
}

}  // namespace

template <class Cfg>
void safe_stop(const BasicSafeStopInput<Cfg>& in, FallbackReason reason, FallbackMemory& memory,
               BasicPlan<Cfg>& out) {
  constexpr int kSamples = Cfg::kTrajectorySamples;
  constexpr Scalar kDt = Cfg::kSpeedHorizon / static_cast<Scalar>(Cfg::kSpeedSamples);
  if (out.status != PlanStatus::kInvalidInput) {
    out.status = PlanStatus::kFallback;
    out.fallback = reason;
  }
  out.trajectory.clear();
  if (out.status == PlanStatus::kInvalidInput) {
    stop_from_last_valid_state(in, in.comfort_decel, out);
    return;
  }
  const scene::BasicScene<Cfg>* scene = in.scene;
  const bool have_state = scene != nullptr && finite_state(scene->ego.state);
  const Scalar v0 = have_state ? max_of(scene->ego.state.v, Scalar(0)) : Scalar(0);
  const Scalar age = in.now - in.previous_time;
  // Where the ego is on the previous plan: its nearest sample.
  Scalar previous_distance2 = -1;
  const bool have_previous = in.previous != nullptr && in.previous->trajectory.size() > 1 && age >= 0 &&
                             age < kFallbackPathAge && have_state;
  const Scalar s_begin = have_previous ? nearest_sample_s(*in.previous, scene->ego.state.x, scene->ego.state.y,
                                                          previous_distance2)
                                       : Scalar(0);
  const bool on_previous =
      have_previous && previous_distance2 <= kFallbackPathDistance * kFallbackPathDistance;
  const bool on_reference =
      !on_previous && have_state && in.reference != nullptr && in.reference->valid();
  geometry::FrenetPoint f = on_reference ? in.reference->to_frenet({scene->ego.state.x, scene->ego.state.y})
                                         : geometry::FrenetPoint{};
  // Hold the lateral offset of the first fallback cycle while fallbacks last,
  // instead of following an ego that drifts with its heading.
  if (on_reference) {
    if (!memory.holding_l) {
      memory.l = f.l;
      memory.holding_l = true;
    }
    f.l = memory.l;
  }
  // Comfortable braking unless it runs into an obstacle on the way; then the
  // vehicle's hard limit (the shortest stop), unless that collides sooner
  // (e.g. with traffic closing in from behind): then comfortable after all.
  // "Comfortable" is the gentlest of comfort_decel .. hard (4 steps) that keeps
  // v^2 |kappa| within lat_acc_max along the path (or within what it is at the
  // start, where braking cannot help): braking along a curved plan from a
  // speed that plan did not expect must not exceed the tyres' share.
  const Scalar hard = have_state && scene->ego.limits.a_min < in.comfort_decel ? scene->ego.limits.a_min
                                                                              : in.comfort_decel;
  const Scalar lat_max = have_state ? scene->ego.limits.lat_acc_max : Scalar(0);
  // The stop at deceleration `decel` (< 0) along the chosen path.
  const auto build = [&](Scalar decel) {
    out.trajectory.clear();
    for (int k = 0; k < kSamples; ++k) {  // kTrajectorySamples
      const Scalar t = kDt * static_cast<Scalar>(k);
      const Scalar t_stop = v0 / -decel;
      const Scalar tt = min_of(t, t_stop);
      const Scalar d = v0 * tt + Scalar(0.5) * decel * tt * tt;
      TrajectoryPoint p;
      p.t = t;
      p.v = max_of(v0 + decel * t, Scalar(0));
      p.a = t < t_stop ? decel : Scalar(0);
      if (on_previous) {
        // Along the previous trajectory by arc length d from where the ego is now.
        pose_along(*in.previous, s_begin + d, p);
      } else if (on_reference) {
        const Scalar s = min_of(f.s + d, in.reference->length());
        const geometry::CurveSample r = in.reference->evaluate(s);
        p.s = s;
        p.l = f.l;
        p.x = r.position.x - f.l * std::sin(r.heading);
        p.y = r.position.y + f.l * std::cos(r.heading);
        p.heading = r.heading;
        p.kappa = r.kappa;
      } else if (have_state) {
        const scene::EgoState& e = scene->ego.state;
        p.x = e.x + d * std::cos(e.heading);
        p.y = e.y + d * std::sin(e.heading);
        p.heading = e.heading;
        p.s = d;
      }
      // Cleared above; kSamples = kTrajectorySamples = capacity.
      static_cast<void>(out.trajectory.push_back(p));
    }
  };
  constexpr int kGentleSteps = 4;
  Scalar gentle = hard;
  for (int j = 0; j < kGentleSteps; ++j) {  // comfort_decel .. hard
    const Scalar decel =
        in.comfort_decel + static_cast<Scalar>(j) / static_cast<Scalar>(kGentleSteps - 1) * (hard - in.comfort_decel);
    build(decel);
    if (!have_state || max_lateral_acceleration(out) <= max_of(lat_max, v0 * v0 * std::fabs(out.trajectory[0].kappa))) {
      gentle = decel;
      break;
    }
  }
  int comfortable_hit = -1;
  for (int attempt = 0; attempt < 3; ++attempt) {  // comfortable, hard, comfortable again
    build(attempt == 1 ? hard : gentle);
    if (!have_state || attempt == 2) {
      break;
    }
    const int hit = first_collision(*scene, in.motions, out, in.lane).sample;
    if (hit < 0 || (attempt == 1 && hit >= comfortable_hit)) {
      break;
    }
    comfortable_hit = hit;
  }
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                   \
  template void safe_stop<C>(const BasicSafeStopInput<C>&, FallbackReason, FallbackMemory&, \
                             BasicPlan<C>&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::planner
