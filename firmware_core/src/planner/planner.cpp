#include "itp/planner/planner.hpp"

#include <cmath>

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"
#include "itp/geometry/frenet.hpp"
#include "itp/scene/scene_digest.hpp"
#include "itp/scene/validation.hpp"

namespace itp::planner {
namespace {

constexpr Scalar kPreviousPlanMaxAge = Scalar(1);  // [s] older plans are neither stitched nor kept to
constexpr Scalar kEverywhere = Scalar(1e9);        // [m] no stop before the end of the map

}  // namespace

const char* to_string(FallbackReason reason) {
  switch (reason) {
    case FallbackReason::kNone: return "none";
    case FallbackReason::kNoDecision: return "no_decision";
    case FallbackReason::kBlocked: return "blocked";
    case FallbackReason::kPathQpFailed: return "path_qp_failed";
    case FallbackReason::kSpeedQpFailed: return "speed_qp_failed";
    case FallbackReason::kCollision: return "collision";
    case FallbackReason::kHorizonTooShort: return "horizon_too_short";
    case FallbackReason::kEvasive: return "evasive";
    case FallbackReason::kBudget: return "budget";
  }
  return "unknown";
}

template <class Cfg>
auto BasicPlanner<Cfg>::spline_workspace() -> SplineWorkspace& {
  if constexpr (Cfg::kShareQpStorage) {
    bool fresh = false;  // the fit writes every entry before it reads it
    return iteration_.qp_arenas().shared.template claim_object<SplineWorkspace>(this, fresh);
  } else {
    return spline_ws_;
  }
}

// Validation, the reference line, the horizon and the scene in its frame.
// false: out.status says invalid input, or the ego is at the end of the map.
template <class Cfg>
bool BasicPlanner<Cfg>::prepare(const Scene& scene, Scalar now, Plan& out) {
  const scene::ValidationResult v = scene::validate(scene, now);
  if (!v.ok()) {
    out.status = PlanStatus::kInvalidInput;
    out.invalid = v.reason;
    return false;
  }
  if (reference_.build(scene.reference_line.span(), spline_workspace()) != geometry::ReferenceLineStatus::kOk) {
    out.status = PlanStatus::kInvalidInput;
    out.invalid = scene::ValidationReason::kReferenceLineSharpTurn;
    return false;
  }
  // Last cycle's path (stitching and the warm start read it by s) in this
  // cycle's frame: the reference line may start at a later polyline point
  // (a sender keeps a window around the ego), which moves s = 0.
  const geometry::Point2 origin = scene.reference_line[0];
  if (last_cycle_ok_ && (origin.x != origin_.x || origin.y != origin_.y)) {
    iteration_.shift_path_frame(reference_.to_frenet(origin_).s);
  }
  origin_ = origin;
  const scene::Ego& ego = scene.ego;
  const Scalar front = scene::front_reach(ego.geometry);
  const Scalar s_start = reference_.to_frenet(geometry::Point2{ego.state.x, ego.state.y}).s;
  // The SL horizon covers where the speed horizon can take the ego, so that
  // no trajectory sample runs past the planned path (and past obstacles the
  // convex space never saw). It may reach beyond the end of the map (the
  // frame continues straight there); the speed plan stops before that end.
  const Scalar v_plan = max_of(max_of(ego.state.v, Scalar(0)), scene.road.speed_limit);
  length_ = clamp(v_plan * Cfg::kSpeedHorizon + front + settings_.stop_margin, Cfg::kPathLength,
                  Cfg::kMaxPathLength);
  map_end_ = reference_.length();
  sl_.build(scene, reference_, now, s_start, s_start + length_, settings_);
  if (map_end_ - s_start < sl_.rear()) {
    return false;  // caller falls back: the ego is at or past the end of the map
  }
  kappa_.sample_reference(reference_, s_start, length_);
  limits_.speed_limit = scene.road.speed_limit;
  limits_.a_max = min_of(ego.limits.a_max, settings_.comfort_accel);
  // Braking: the vehicle's hard limit bounds the speed QP (so that an emergency
  // stays feasible); the QP's cost on s̈ keeps ordinary braking gentle.
  limits_.a_min = ego.limits.a_min;
  limits_.lat_acc_max = ego.limits.lat_acc_max;
  limits_.kappa_max = ego.limits.kappa_max;
  return true;
}

// init_sl and init_st: the ego state in the Frenet frame, or, when the ego
// still follows the previous plan within the replan thresholds, that plan's
// state at this time (stitching: consecutive plans join without a jump).
template <class Cfg>
StartState BasicPlanner<Cfg>::start_state(const Scene& scene, Scalar now) const {
  const scene::EgoState& e = scene.ego.state;
  geometry::CurveSample r;
  const geometry::FrenetPoint f = reference_.to_frenet(geometry::Point2{e.x, e.y}, r);
  const geometry::FrenetState fs =
      geometry::to_frenet_state(r, f.l, geometry::CartesianState{{e.x, e.y}, e.heading, e.kappa, e.v, e.a});
  StartState st;
  st.s = f.s;
  st.l = f.l;
  st.dl = fs.dl;
  st.ddl = fs.ddl;
  st.v = fs.ds;
  st.a = fs.dds;
  const path::BasicPathResult<Cfg>& path = iteration_.path();
  const speed::BasicSpeedResult<Cfg>& speed = iteration_.speed();
  const Scalar age = now - previous_time_;
  if (have_previous_ && last_cycle_ok_ && age >= 0 && age < kPreviousPlanMaxAge &&
      path.status == qp::QpStatus::kOptimal && speed.status == qp::QpStatus::kOptimal) {
    const Scalar s_plan = path.s0 + speed.eval(age, 0);
    const Scalar l_plan = path.eval(f.s, 0);
    const Scalar v_plan = speed.eval(age, 1);
    if (std::fabs(l_plan - f.l) < settings_.replan_lateral &&
        std::fabs(s_plan - f.s) < settings_.replan_longitudinal &&
        std::fabs(v_plan - st.v) < settings_.replan_speed) {
      st.stitched_age = age;
      st.l = l_plan;
      st.dl = path.eval(f.s, 1);
      st.ddl = path.eval(f.s, 2);
      st.v = max_of(v_plan, Scalar(0));
      st.a = speed.eval(age, 2);
    }
  }
  st.a = clamp(st.a, limits_.a_min, limits_.a_max);
  st.dl = clamp(st.dl, -Scalar(0.5), Scalar(0.5));
  const Scalar kappa_ref = kappa_.reference.at(st.s);
  st.ddl = clamp(st.ddl, -limits_.kappa_max - kappa_ref, limits_.kappa_max - kappa_ref);
  return st;
}

// Path s the ego's front must stop before when nothing else stops it: the
// end of the map, less the stop margin.
template <class Cfg>
Scalar BasicPlanner<Cfg>::stop_before_map_end() const {
  return min_of(kEverywhere + sl_.front(), map_end_) - settings_.stop_margin;
}

template <class Cfg>
void BasicPlanner<Cfg>::stop_safely(const Scene* scene, Scalar now, FallbackReason reason, Plan& out) {
  BasicSafeStopInput<Cfg> in;
  in.scene = scene;
  in.now = now;
  in.previous = have_previous_ ? &previous_ : nullptr;
  in.previous_time = previous_time_;
  in.reference = &reference_;
  in.motions = sl_.motions();
  in.lane = EgoLane{sl_.lane_target(), sl_.road().lane_width};
  in.comfort_decel = settings_.comfort_decel;
  safe_stop(in, reason, fallback_memory_, out);
}

// The answer to a request equal to the last one: that cycle's plan again.
// (Planning it anew would stitch onto that plan at age 0 and hotstart from
// its QPs: a different plan, defect 11.)
template <class Cfg>
void BasicPlanner<Cfg>::reset() {
  have_last_digest_ = false;
  have_previous_ = false;
  last_cycle_ok_ = false;
  fallback_memory_ = FallbackMemory{};
  iteration_.reset();
}

template <class Cfg>
auto BasicPlanner<Cfg>::plan(const PlanRequest& request) -> const Plan& {
  const std::uint64_t t_begin = ticks_.ticks();
  Plan& out = output_;
  iteration_.begin_cycle();
  const std::uint64_t digest = request.scene != nullptr ? scene::digest(*request.scene, request.now) : 0;
  if (request.scene != nullptr && have_last_digest_ && digest == last_digest_) {
    // The same scene again: the same plan (output_ still holds it).
    out.timing = StageTiming{};
    out.timing.tick_hz = ticks_.hz;
    out.timing.total = ticks_.ticks() - t_begin;
    return out;
  }
  out = Plan{};
  out.timing.tick_hz = ticks_.hz;
  if (request.scene == nullptr) {
    out.status = PlanStatus::kInvalidInput;
    stop_safely(nullptr, request.now, FallbackReason::kNone, out);
    have_last_digest_ = false;  // output_ no longer holds the last scene's plan
    return out;
  }
  const Scene& scene = *request.scene;
  const bool prepared = prepare(scene, request.now, out);
  out.timing.prepare = ticks_.ticks() - t_begin;
  if (!prepared) {
    stop_safely(&scene, request.now,
                out.status == PlanStatus::kInvalidInput ? FallbackReason::kNone : FallbackReason::kHorizonTooShort,
                out);
  } else {
    const StartState start = start_state(scene, request.now);
    typename Iteration::Context ctx;
    ctx.scene = &scene;
    ctx.reference = &reference_;
    ctx.sl = &sl_;
    ctx.bounds = &kappa_;
    ctx.inputs = make_cycle_inputs(start, scene, limits_, kappa_, settings_, sl_.front(), sl_.rear(), length_,
                                   stop_before_map_end());
    ctx.limits = limits_;
    ctx.map_end = map_end_;
    ctx.settings = &settings_;
    const bool recent = have_previous_ && !(request.now - previous_time_ > kPreviousPlanMaxAge);
    ctx.previous = PreviousSides{recent ? previous_.decisions.span() : std::span<const ObstacleDecision>{}};
    ctx.first_cycle = !have_previous_;
    ctx.ticks = ticks_;
    const FallbackReason failed = iteration_.run(ctx, start, out);
    if (failed != FallbackReason::kNone) {
      stop_safely(&scene, request.now, failed, out);
    }
  }
  out.timing.total = ticks_.ticks() - t_begin;
  // The last ok plan stays for stitching, hysteresis and the fallback's path;
  // a fallback does not erase it (it ages out instead).
  if (out.status == PlanStatus::kOk) {
    previous_ = out;
    previous_time_ = request.now;
    have_previous_ = true;
    fallback_memory_.holding_l = false;
  }
  last_cycle_ok_ = out.status == PlanStatus::kOk;
  last_digest_ = digest;
  have_last_digest_ = true;
  return out;
}

// Explicit instantiations for every configuration (itp/configurations.hpp),
// each within its memory budget.
#define ITP_INSTANTIATE(C)        \
  template class BasicPlanner<C>; \
  static_assert(sizeof(BasicPlanner<C>) <= C::kPlannerBytesBudget, "planner over its memory budget");
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::planner
