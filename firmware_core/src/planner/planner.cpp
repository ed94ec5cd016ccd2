#include "itp/planner/planner.hpp"

#include <cmath>

#include "itp/collision/oriented_box.hpp"
#include "itp/configurations.hpp"
#include "itp/decision/corridor.hpp"
#include "itp/geometry/angle.hpp"
#include "itp/geometry/frenet.hpp"
#include "itp/planner/road_prediction.hpp"
#include "itp/scene/obstacle_motion.hpp"
#include "itp/scene/validation.hpp"

namespace itp::planner {
namespace {

constexpr Scalar kPreviousPlanMaxAge = Scalar(1);  // [s] older plans are not stitched
constexpr int kMaxPathAttempts = 4;                // decisions tried by the path QP per iteration
constexpr int kEvasiveAttempts = 2;                // ... of which this many with the evasive bound too
constexpr Scalar kFallbackPathAge = Scalar(1);    // [s] a fallback brakes along the last ok plan this long
constexpr Scalar kOncomingHeading =
    Scalar(1.5707963267948966);  // [rad] |heading - reference| beyond: oncoming
// A mover heading across the road (45..135 deg from the reference) at walking
// pace or more crosses the path: the ego yields to it in the ST graph. Its box
// at the meeting time is a snapshot of something that moves sideways, so a
// lateral decision around it means nothing, and its sweep covers the road.
constexpr Scalar kCrossingHeadingLow = Scalar(0.7853981633974483);   // [rad]
constexpr Scalar kCrossingHeadingHigh = Scalar(2.356194490192345);   // [rad]
constexpr Scalar kCrossingMinSpeed = Scalar(0.5);                    // [m/s]
// A crossing mover (a pedestrian, a cyclist) walks into the path: the ego
// does not pass before it unless it is this much further away sideways.
constexpr Scalar kCrossingMargin = Scalar(1.0);                      // [m]
constexpr Scalar kEverywhere = Scalar(1e9);                          // [m] an s-range without bounds
// A car alongside in another lane at least this close to the ego's speed
// (or faster) is treated as coming from behind: its lane ahead is its own.
constexpr Scalar kAlongsideSpeedSlack = Scalar(1);                   // [m/s]

Scalar min_of(Scalar a, Scalar b) { return a < b ? a : b; }
Scalar max_of(Scalar a, Scalar b) { return a > b ? a : b; }
Scalar clamp(Scalar v, Scalar lo, Scalar hi) { return v < lo ? lo : (v > hi ? hi : v); }

// A road edge moved inwards by `shift` (> 0: towards the left).
template <class Cfg>
decision::BasicLateralProfile<Cfg> to_profile(const scene::BasicBoundary<Cfg>& b, Scalar shift) {
  if (b.is_constant()) {
    return decision::BasicLateralProfile<Cfg>::constant(b.offset + shift);
  }
  decision::BasicLateralProfile<Cfg> p;
  for (const scene::BoundaryPoint& q : b.table) {  // <= kMaxBoundaryPoints
    static_cast<void>(p.add(q.s, q.l + shift));
  }
  return p;
}

collision::OrientedBox obstacle_box(Scalar x, Scalar y, Scalar heading, Scalar length, Scalar width) {
  return collision::OrientedBox{x, y, heading, length, width};
}

// SL box of a moving obstacle from one projection of its centre: the box's
// half extents along and across the reference at its relative heading. Its
// error on a curved road is about κ·L²/8 (6 cm for a 5 m car on a 50 m
// radius), well inside the dynamic margin; 355 boxes per cycle make the exact
// edge-sampled version (about 20 projections each) the planner's largest cost.
template <class Cfg>
decision::SlBox moving_box_sl(const geometry::BasicReferenceLine<Cfg>& line, Scalar x, Scalar y,
                              Scalar heading, Scalar length, Scalar width, Scalar margin,
                              std::int32_t id) {
  geometry::CurveSample foot;
  const geometry::FrenetPoint c = line.to_frenet(geometry::Point2{x, y}, foot);
  const Scalar rel = geometry::relative_heading(heading, foot.heading);
  const Scalar cs = std::fabs(std::cos(rel));
  const Scalar sn = std::fabs(std::sin(rel));
  const Scalar half_s = Scalar(0.5) * (cs * length + sn * width) + margin;
  const Scalar half_l = Scalar(0.5) * (sn * length + cs * width) + margin;
  return decision::SlBox{c.s - half_s, c.s + half_s, c.l - half_l, c.l + half_l, id, true};
}

bool finite_state(const scene::EgoState& e) {
  return std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.heading) && std::isfinite(e.v);
}

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
  }
  return "unknown";
}

// --- Preparation ------------------------------------------------------------

template <class Cfg>
bool BasicPlanner<Cfg>::prepare(const Scene& scene, Scalar now, Plan& out) {
  const scene::ValidationResult v = scene::validate(scene);
  if (!v.ok()) {
    out.status = PlanStatus::kInvalidInput;
    out.invalid = v.reason;
    return false;
  }
  if (reference_.build(scene.reference_line.span(), spline_ws_) != geometry::ReferenceLineStatus::kOk) {
    out.status = PlanStatus::kInvalidInput;
    out.invalid = scene::ValidationReason::kReferenceLineSharpTurn;
    return false;
  }
  // Last cycle's path (stitching and the warm start read it by s) in this
  // cycle's frame: the reference line may start at a later polyline point
  // (a sender keeps a window around the ego), which moves s = 0.
  const geometry::Point2 origin = scene.reference_line[0];
  if (last_cycle_ok_ && (origin.x != origin_.x || origin.y != origin_.y)) {
    path_.s0 += reference_.to_frenet(origin_).s;
  }
  origin_ = origin;
  const scene::Ego& ego = scene.ego;
  rear_ = Scalar(0.5) * (ego.geometry.length - ego.geometry.wheelbase);
  front_ = ego.geometry.length - rear_;
  const geometry::FrenetPoint f = reference_.to_frenet(geometry::Point2{ego.state.x, ego.state.y});
  s_start_ = f.s;
  ego_l_ = f.l;
  ego_v_ = ego.state.v;
  // The SL horizon covers where the speed horizon can take the ego, so that
  // no trajectory sample runs past the planned path (and past obstacles the
  // convex space never saw). It may reach beyond the end of the map (the
  // frame continues straight there); the speed plan stops before that end.
  const Scalar v_plan = max_of(max_of(ego.state.v, Scalar(0)), scene.road.speed_limit);
  length_ = clamp(v_plan * Cfg::kSpeedHorizon + front_ + settings_.stop_margin, Cfg::kPathLength,
                  Cfg::kMaxPathLength);
  map_end_ = reference_.length();
  if (map_end_ - f.s < rear_) {
    return false;  // caller falls back: the ego is at or past the end of the map
  }
  kappa_.s0 = s_start_;
  kappa_.ds = length_ / static_cast<Scalar>(Cfg::kCurvatureSamples - 1);
  for (int i = 0; i < Cfg::kCurvatureSamples; ++i) {  // Cfg::kCurvatureSamples
    kappa_.kappa[static_cast<std::size_t>(i)] =
        reference_.evaluate(kappa_.s0 + kappa_.ds * static_cast<Scalar>(i)).kappa;
  }
  road_.left = to_profile(scene.road.left, -settings_.road_margin);
  road_.right = to_profile(scene.road.right, settings_.road_margin);
  road_.lane_width = scene.road.lane_width;
  lane_target_ = scene.road.target_lane_offset;
  road_.target_lane_offset = scene.road.target_lane_offset;
  limits_.speed_limit = scene.road.speed_limit;
  limits_.a_max = min_of(ego.limits.a_max, settings_.comfort_accel);
  // Braking: the vehicle's hard limit bounds the speed QP (so that an emergency
  // stays feasible); the QP's cost on s̈ keeps ordinary braking gentle.
  limits_.a_min = ego.limits.a_min;
  limits_.a_lat_max = ego.limits.lat_acc_max;
  limits_.kappa_max = ego.limits.kappa_max;
  project_obstacles(scene, now);
  return true;
}

template <class Cfg>
void BasicPlanner<Cfg>::project_obstacles(const Scene& scene, Scalar now) {
  boxes_.clear();
  for (const scene::StaticObstacle& o : scene.static_obstacles) {  // <= kMaxStaticObstacles
    const geometry::SLBox b = geometry::sl_bounding_box(
        reference_, geometry::OrientedBox{{o.x, o.y}, o.heading, o.length, o.width}, settings_.static_margin);
    // Inflated in s by the ego's extents, so constraints on the rear axle cover the car.
    decision::SlBox sl{b.s_min - front_, b.s_max + rear_, b.l_min, b.l_max, o.id, false};
    static_cast<void>(boxes_.push_back(sl));
  }
  track_count_ = 0;
  for (const DynamicObstacle& o : scene.dynamic_obstacles) {  // <= kMaxDynamicObstacles
    DynamicTrack& tr = tracks_[static_cast<std::size_t>(track_count_++)];
    tr.id = o.id;
    tr.sweep_occupied = false;
    tr.from_behind = false;
    tr.follower = false;
    tr.crossing = false;
    bool seen = false;
    bool on_road = false;  // first seen on the road: its prediction stays there
    std::array<scene::ObstacleSample, Cfg::kStSamples>& motion = motion_[static_cast<std::size_t>(track_count_ - 1)];
    static_cast<void>(predict_along_road(reference_, road_, o, now, kDt, motion));
    for (int k = 0; k < kSamples; ++k) {  // Cfg::kStSamples
      const auto u = static_cast<std::size_t>(k);
      const scene::ObstacleSample& p = motion[u];
      tr.present[u] = p.present;
      if (!p.present) {
        continue;
      }
      tr.box[u] = moving_box_sl(reference_, p.x, p.y, p.heading, o.length, o.width, settings_.dynamic_margin, o.id);
      const Scalar s_mid = Scalar(0.5) * (tr.box[u].s_min + tr.box[u].s_max);
      // Classified where first seen on the reference line (behind its start
      // the frame runs straight on, so lanes mean nothing there).
      if (!seen && (s_mid >= 0 || k == kSamples - 1)) {
        seen = true;
        const Scalar rel = geometry::relative_heading(p.heading, reference_.evaluate(s_mid).heading);
        const bool oncoming = std::fabs(rel) > kOncomingHeading;
        const Scalar l_mid = Scalar(0.5) * (tr.box[u].l_min + tr.box[u].l_max);
        // Approaching from behind, or alongside and not slower, in another
        // lane than the ego's target lane: the ego must not move in (or stay)
        // ahead of it (it would be in its way). A follower in the target lane
        // is its own business.
        const bool behind = tr.box[u].s_max < s_start_;
        const bool alongside = tr.box[u].s_min < s_start_ + front_ &&
                               p.v * std::cos(rel) >= ego_v_ - kAlongsideSpeedSlack;
        const bool other_lane = std::fabs(l_mid - lane_target_) > Scalar(0.5) * road_.lane_width;
        const bool from_behind = (behind || alongside) && other_lane;
        tr.crossing = std::fabs(rel) > kCrossingHeadingLow && std::fabs(rel) < kCrossingHeadingHigh &&
                      std::fabs(p.v) >= kCrossingMinSpeed;
        tr.sweep_occupied = !tr.crossing && (oncoming || from_behind);
        tr.from_behind = tr.sweep_occupied && !oncoming;
        const bool ego_in_lane = std::fabs(ego_l_ - lane_target_) < Scalar(0.5) * road_.lane_width;
        // (behind where the ego is by then at its speed: it may be first seen
        // on the reference line a few samples on)
        const bool behind_then = tr.box[u].s_max < s_start_ + max_of(ego_v_, Scalar(0)) * kDt * static_cast<Scalar>(k);
        tr.follower = behind_then && !other_lane && ego_in_lane && !oncoming && !tr.crossing;
        on_road = l_mid > road_.right.at(s_mid) && l_mid < road_.left.at(s_mid);
      }
      if (tr.crossing) {
        tr.box[u].l_min -= kCrossingMargin;
        tr.box[u].l_max += kCrossingMargin;
      } else if (on_road) {
        keep_on_road(s_mid, tr.box[u]);
      }
    }
  }
}

// Road users seen on the road stay on it: a constant-velocity prediction on a
// curve runs off along the tangent, so its boxes are shifted back inside the
// road edges (when they fit), where the road bends the real obstacle.
template <class Cfg>
void BasicPlanner<Cfg>::keep_on_road(Scalar s, decision::SlBox& box) const {
  const Scalar lo = road_.right.at(s);
  const Scalar hi = road_.left.at(s);
  if (box.l_max - box.l_min > hi - lo) {
    return;
  }
  const Scalar shift = box.l_max > hi ? hi - box.l_max : (box.l_min < lo ? lo - box.l_min : Scalar(0));
  box.l_min += shift;
  box.l_max += shift;
}

// Dynamic obstacles enter the convex space where the ego meets them: the first
// sample at which the ego's guessed position lies within the obstacle's
// s-extent (grown by the ego's length); obstacles the ego never reaches sit at
// their last predicted place; `skip` marks those left to the ST graph alone.
template <class Cfg>
int BasicPlanner<Cfg>::place_dynamic(const std::array<Scalar, Cfg::kStSamples>& s_guess,
                                     bool* skip) {
  int placed = 0;
  for (int i = 0; i < track_count_; ++i) {  // <= kMaxDynamicObstacles
    const DynamicTrack& tr = tracks_[static_cast<std::size_t>(i)];
    if (skip[i] || tr.crossing || tr.follower) {
      continue;
    }
    int meet = -1;
    int last = -1;
    for (int k = 0; k < kSamples && meet < 0; ++k) {  // Cfg::kStSamples
      const auto u = static_cast<std::size_t>(k);
      if (!tr.present[u]) {
        continue;
      }
      last = k;
      const Scalar ego_s = s_start_ + s_guess[u];
      if (ego_s >= tr.box[u].s_min - front_ && ego_s <= tr.box[u].s_max + rear_) {
        meet = k;
      }
    }
    const int k = meet >= 0 ? meet : last;
    if (k < 0 || tr.box[static_cast<std::size_t>(k)].s_max + rear_ < s_start_) {
      continue;  // never present, or only behind the ego
    }
    if (meet < 0 && !tr.sweep_occupied &&
        tr.box[static_cast<std::size_t>(k)].s_max + rear_ < s_start_ + s_guess[static_cast<std::size_t>(k)]) {
      continue;  // never met, and behind the ego at the end: the ego passed it (the ST graph still sees it)
    }
    decision::SlBox b = tr.box[static_cast<std::size_t>(k)];
    if (tr.sweep_occupied) {
      // An oncoming obstacle sweeps its way towards and past the ego: the ego
      // cannot pass it on the side it comes from, nor use its lane in between
      // (a manoeuvre there that stalls leaves the ego in its way). The same
      // holds for traffic coming up from behind in another lane: cutting in
      // ahead of it and slowing down gets the ego hit. Its box is everything
      // it covers over the horizon from the ego on (behind the ego nothing is
      // planned, and behind the reference line's start the frame runs
      // straight, not along the lanes).
      // Traffic from behind that moves over into the ego's target lane
      // becomes a follower there (its own business, RSS): its sweep covers
      // only the lane(s) it comes from, never the target lane.
      const Scalar half_lane = Scalar(0.5) * road_.lane_width;
      bool any = false;
      for (int j = 0; j < kSamples; ++j) {  // Cfg::kStSamples
        const auto u = static_cast<std::size_t>(j);
        const Scalar s_mid = Scalar(0.5) * (tr.box[u].s_min + tr.box[u].s_max);
        if (!tr.present[u] || tr.box[u].s_max < s_start_ - rear_ || s_mid < 0) {
          continue;
        }
        decision::SlBox q = tr.box[u];
        if (tr.from_behind) {
          const Scalar l_mid = Scalar(0.5) * (q.l_min + q.l_max);
          if (std::fabs(l_mid - lane_target_) < half_lane) {
            continue;  // in the target lane: a follower there
          }
          if (l_mid > lane_target_) {
            q.l_min = max_of(q.l_min, lane_target_ + half_lane);
          } else {
            q.l_max = min_of(q.l_max, lane_target_ - half_lane);
          }
        }
        if (!any && tr.from_behind) {
          b = q;  // not the meeting box: it may lie in the target lane
        }
        any = true;
        b.s_min = min_of(b.s_min, q.s_min);
        b.s_max = max_of(b.s_max, q.s_max);
        b.l_min = min_of(b.l_min, q.l_min);
        b.l_max = max_of(b.l_max, q.l_max);
      }
      if (tr.from_behind && !any) {
        continue;  // all of it ahead of the ego lies in the target lane
      }
    }
    b.s_min -= front_;
    b.s_max += rear_;
    if (boxes_.push_back(b)) {
      ++placed;
    }
  }
  return placed;
}

template <class Cfg>
typename BasicPlanner<Cfg>::Start BasicPlanner<Cfg>::start_state(const Scene& scene,
                                                                 Scalar now) const {
  const scene::EgoState& e = scene.ego.state;
  geometry::CurveSample r;
  const geometry::FrenetPoint f = reference_.to_frenet(geometry::Point2{e.x, e.y}, r);
  Start st;
  st.s = f.s;
  st.l = f.l;
  const Scalar one = Scalar(1) - r.kappa * f.l;
  const Scalar dtheta = geometry::relative_heading(e.heading, r.heading);
  const Scalar c = std::cos(dtheta);
  st.dl = geometry::lateral_slope(e.heading, r.heading, r.kappa, f.l);
  st.ddl = (e.kappa * one / c - r.kappa) * one / (c * c);
  st.v = e.v * c / one;
  st.a = e.a * c / one;
  // Stitching: start from the previous plan where the ego is now, unless it
  // has deviated beyond the thresholds (then replan from the ego state).
  const Scalar age = now - previous_time_;
  if (have_previous_ && last_cycle_ok_ && age >= 0 && age < kPreviousPlanMaxAge &&
      path_.status == qp::QpStatus::kOptimal && speed_.status == qp::QpStatus::kOptimal) {
    const Scalar s_plan = path_.s0 + speed_.eval(age, 0);
    const Scalar l_plan = path_.eval(f.s, 0);
    const Scalar v_plan = speed_.eval(age, 1);
    if (std::fabs(l_plan - f.l) < settings_.replan_lateral &&
        std::fabs(s_plan - f.s) < settings_.replan_longitudinal &&
        std::fabs(v_plan - st.v) < settings_.replan_speed) {
      st.stitched_age = age;
      st.l = l_plan;
      st.dl = path_.eval(f.s, 1);
      st.ddl = path_.eval(f.s, 2);
      st.v = max_of(v_plan, Scalar(0));
      st.a = speed_.eval(age, 2);
    }
  }
  st.a = clamp(st.a, limits_.a_min, limits_.a_max);
  st.dl = clamp(st.dl, -Scalar(0.5), Scalar(0.5));
  st.ddl = clamp(st.ddl, -limits_.kappa_max - kappa_.at(st.s), limits_.kappa_max - kappa_.at(st.s));
  return st;
}

// The path's curvature bound at the speed the ego is expected to have there:
// min(κ_max, a_lat_max / v²), never below the reference's own curvature (the
// speed stage slows the ego for that). v(s) is read off the guessed s(t), v(t).
template <class Cfg>
void BasicPlanner<Cfg>::update_kappa_bound(const std::array<Scalar, Cfg::kStSamples>& s_guess,
                                           const std::array<Scalar, Cfg::kStSamples>& v_guess) {
  kappa_bound_.s0 = kappa_.s0;
  kappa_bound_.ds = kappa_.ds;
  int k = 0;
  for (int i = 0; i < Cfg::kCurvatureSamples; ++i) {  // Cfg::kCurvatureSamples
    const Scalar s_rel = kappa_.ds * static_cast<Scalar>(i);
    while (k + 1 < kSamples && s_guess[static_cast<std::size_t>(k + 1)] <
                                   s_rel) {  // monotone, < Cfg::kStSamples in all
      ++k;
    }
    const Scalar v = max_of(v_guess[static_cast<std::size_t>(k)], Scalar(1));
    const Scalar kr = std::fabs(kappa_.kappa[static_cast<std::size_t>(i)]);
    Scalar kb = min_of(limits_.kappa_max, limits_.a_lat_max / (v * v));
    kb = max_of(kb, min_of(kr + Scalar(0.002), limits_.kappa_max));
    kappa_bound_.kappa[static_cast<std::size_t>(i)] = kb;
  }
}

// The path's curvature bound when the expected-speed one cannot be met: what
// the ego can still take at the slowest speed it can have at each s,
// braking at its limit (after the speed spline's 0.3 s onset):
// min(κ_max, a_lat_max / v_min(s)²). Near the ego that is the expected-speed
// bound (it cannot slow down at once), so a path never asks for a swerve the
// speed stage cannot make within the lateral-acceleration limit.
template <class Cfg>
void BasicPlanner<Cfg>::update_kappa_reach(CurvatureProfile& out, Scalar v0, Scalar a_lat) const {
  constexpr Scalar kOnset = Scalar(0.3);  // [s] as the ST graph's braking model
  out.s0 = kappa_.s0;
  out.ds = kappa_.ds;
  const Scalar v = max_of(v0, Scalar(0));
  const Scalar brake = -limits_.a_min;  // > 0
  for (int i = 0; i < Cfg::kCurvatureSamples; ++i) {  // Cfg::kCurvatureSamples
    const Scalar s = kappa_.ds * static_cast<Scalar>(i);
    const Scalar braked = max_of(s - v * kOnset, Scalar(0));
    const Scalar v_min = std::sqrt(max_of(v * v - Scalar(2) * brake * braked, Scalar(0)));
    const Scalar kr = std::fabs(kappa_.kappa[static_cast<std::size_t>(i)]);
    Scalar kb = v_min > Scalar(1) ? min_of(limits_.kappa_max, a_lat / (v_min * v_min)) : limits_.kappa_max;
    kb = max_of(kb, min_of(kr + Scalar(0.002), limits_.kappa_max));
    out.kappa[static_cast<std::size_t>(i)] = kb;
  }
}

// Kept decisions with a usable coarse QP, by decision cost (eq. 4) plus the
// hysteresis bonus for keeping last cycle's sides; ties keep the geometric rank.
template <class Cfg>
int BasicPlanner<Cfg>::rank_decisions(std::array<int, Cfg::kKeptDecisions>& order) const {
  std::array<Scalar, Cfg::kKeptDecisions> cost{};
  int n = 0;
  for (std::size_t i = 0; i < decision_.decisions().kept.size(); ++i) {  // <= kKeptDecisions
    if (!qp::is_usable(decision_.coarse(i).status)) {
      continue;
    }
    const CoarseResult& cr = decision_.coarse(i);
    Scalar c = cr.decision_cost - hysteresis_bonus(static_cast<int>(i));
    if (!decision_.decisions().kept[i].reaches_end && cr.samples > 0) {
      // A stop before a blockage waits in the target lane, not half-way into
      // another one (where oncoming traffic may come).
      c += settings_.blocked_lane_weight * std::fabs(cr.l[static_cast<std::size_t>(cr.samples - 1)] - lane_target_);
    }
    cost[static_cast<std::size_t>(n)] = c;
    order[static_cast<std::size_t>(n)] = static_cast<int>(i);
    ++n;
  }
  for (int i = 1; i < n; ++i) {  // insertion sort, stable; n <= kKeptDecisions
    const Scalar c = cost[static_cast<std::size_t>(i)];
    const int o = order[static_cast<std::size_t>(i)];
    int j = i - 1;
    for (; j >= 0 && cost[static_cast<std::size_t>(j)] > c; --j) {
      cost[static_cast<std::size_t>(j + 1)] = cost[static_cast<std::size_t>(j)];
      order[static_cast<std::size_t>(j + 1)] = order[static_cast<std::size_t>(j)];
    }
    cost[static_cast<std::size_t>(j + 1)] = c;
    order[static_cast<std::size_t>(j + 1)] = o;
  }
  return n;
}

// Frame-to-frame consistency: a decision that passes every obstacle of the
// previous cycle's plan on the same side as that plan did earns a bonus, so
// that near-equal alternatives do not flip between cycles. Passing a moving
// obstacle on the other side than the last plan costs far more: the path
// would swing across its lane within a second or two (lateral acceleration
// beyond any limit when tracked), so any decision that keeps those sides is
// tried first.
template <class Cfg>
Scalar BasicPlanner<Cfg>::hysteresis_bonus(int index) const {
  if (!have_previous_ || previous_.decisions.empty() || now_ - previous_time_ > kPreviousPlanMaxAge) {
    return 0;
  }
  const Decision& d = decision_.decisions().kept[static_cast<std::size_t>(index)];
  int compared = 0;
  bool static_flip = false;
  for (const decision::SlBox& b : boxes_) {  // <= kMaxObstacles
    for (const ObstacleDecision& od : previous_.decisions) {  // <= kMaxObstacles
      if (od.obstacle != b.obstacle_id || od.dynamic != b.dynamic || od.lateral == LateralSide::kNone) {
        continue;
      }
      const decision::Side side = decision::side_of(decision_.space(), d, b);
      const LateralSide now = side == decision::Side::kLeft ? LateralSide::kLeft
                              : side == decision::Side::kRight ? LateralSide::kRight
                                                               : LateralSide::kNone;
      if (now != od.lateral && now != LateralSide::kNone) {
        if (b.dynamic) {
          return -settings_.moving_side_flip_cost;
        }
        static_flip = true;
      }
      ++compared;
    }
  }
  return compared > 0 && !static_flip ? settings_.hysteresis : Scalar(0);
}

// --- Output ----------------------------------------------------------------

template <class Cfg>
void BasicPlanner<Cfg>::sample_trajectory(const Start& start, Plan& out) const {
  out.trajectory.clear();
  for (int k = 0; k < kSamples; ++k) {  // kTrajectorySamples
    const Scalar t = kDt * static_cast<Scalar>(k);
    const Scalar s = start.s + speed_.eval(t, 0);
    const geometry::CurveSample r = reference_.evaluate(s);
    geometry::FrenetState f;
    f.ds = max_of(speed_.eval(t, 1), Scalar(0));
    f.dds = speed_.eval(t, 2);
    f.l = path_.eval(s, 0);
    f.dl = path_.eval(s, 1);
    f.ddl = path_.eval(s, 2);
    f.ref_kappa = r.kappa;
    f.ref_dkappa = r.dkappa;
    const geometry::CartesianMotion m = geometry::cartesian_motion(f);
    TrajectoryPoint p;
    p.t = t;
    p.s = s;
    p.l = f.l;
    p.x = r.position.x - f.l * std::sin(r.heading);
    p.y = r.position.y + f.l * std::cos(r.heading);
    p.heading = geometry::wrap_angle(r.heading + m.relative_heading);
    p.kappa = m.kappa;
    p.v = m.v;
    p.a = m.a;
    static_cast<void>(out.trajectory.push_back(p));
  }
}

// RSS's rule for the car behind (Shalev-Shwartz et al. 2017): it keeps the
// safe distance to the car ahead whatever that car does short of braking
// beyond b_max; it is responsible for a rear-end collision. A predicted hit
// at plan sample k is such a one when the mover comes along the ego's way
// (heading within 45 deg) from behind (its centre behind the ego's rear
// bumper, its footprint reaching into the ego's from there), faster than the
// ego, and the ego kept to its target lane from the start of the plan to
// the hit (it did not cut in ahead of the mover). No plan of the ego can
// remove such a hit without braking less for what lies ahead or leaving
// its lane in front of other traffic, so it does not make the plan unsafe.
template <class Cfg>
bool BasicPlanner<Cfg>::follower_runs_in(const Plan& plan, std::size_t k,
                                         const scene::ObstacleSample& o,
                                         const scene::ObstacleSample* before) const {
  const TrajectoryPoint& p = plan.trajectory[k];
  const Scalar rel = geometry::relative_heading(o.heading, p.heading);
  if (std::fabs(rel) > kCrossingHeadingLow) {
    return false;
  }
  const Scalar c = std::cos(p.heading);
  const Scalar sn = std::sin(p.heading);
  const Scalar half_length = Scalar(0.5) * (front_ + rear_);
  const Scalar centre = half_length - rear_;  // rear axle to the ego's centre
  const Scalar along = (o.x - p.x) * c + (o.y - p.y) * sn - centre;
  // Its speed along the ego's heading: from its motion over the last step
  // when there is one (a recorded trajectory's speeds need not match it).
  const Scalar v_along = before != nullptr && before->present
                             ? ((o.x - before->x) * c + (o.y - before->y) * sn) / kDt
                             : o.v * std::cos(rel);
  if (along > -half_length || v_along <= max_of(p.v, Scalar(0))) {
    return false;
  }
  const Scalar half_lane = Scalar(0.5) * road_.lane_width;
  for (std::size_t j = 0; j <= k; ++j) {  // <= kTrajectorySamples
    if (std::fabs(plan.trajectory[j].l - lane_target_) > half_lane) {
      return false;
    }
  }
  return true;
}

// Index of the first trajectory sample whose footprint overlaps an obstacle
// (its id in `*hit_id` when given); -1: none. A follower running into the
// ego from behind is its own responsibility (follower_runs_in).
template <class Cfg>
int BasicPlanner<Cfg>::first_collision(const Scene& scene, const Plan& plan,
                                       std::int32_t* hit_id) const {
  const scene::VehicleGeometry& g = scene.ego.geometry;
  bool rear_ended[Cfg::kMaxDynamicObstacles] = {};
  for (std::size_t k = 0; k < plan.trajectory.size(); ++k) {  // kTrajectorySamples
    const TrajectoryPoint& p = plan.trajectory[k];
    const collision::OrientedBox ego = collision::box_from_rear_axle(p.x, p.y, p.heading, g.length, g.width, rear_);
    for (const scene::StaticObstacle& o : scene.static_obstacles) {  // <= kMaxStaticObstacles
      if (collision::overlap(ego, obstacle_box(o.x, o.y, o.heading, o.length, o.width))) {
        if (hit_id != nullptr) {
          *hit_id = o.id;
        }
        return static_cast<int>(k);
      }
    }
    for (std::size_t i = 0; i < scene.dynamic_obstacles.size(); ++i) {  // <= kMaxDynamicObstacles
      const DynamicObstacle& o = scene.dynamic_obstacles[i];
      const scene::ObstacleSample& q = motion_[i][k];  // the motion planned against, at p.t
      if (!q.present || rear_ended[i] ||
          !collision::overlap(ego, obstacle_box(q.x, q.y, q.heading, o.length, o.width))) {
        continue;
      }
      // A rear-end stays one as the footprints go on overlapping.
      rear_ended[i] = follower_runs_in(plan, k, q, k > 0 ? &motion_[i][k - 1] : nullptr);
      if (!rear_ended[i]) {
        if (hit_id != nullptr) {
          *hit_id = o.id;
        }
        return static_cast<int>(k);
      }
    }
  }
  return -1;
}

template <class Cfg>
void BasicPlanner<Cfg>::record_decisions(Plan& out) const {
  out.decisions.clear();
  if (chosen_ < 0) {
    return;
  }
  const Decision& d = decision_.decisions().kept[static_cast<std::size_t>(chosen_)];
  for (const decision::SlBox& b : boxes_) {  // <= kMaxObstacles
    ObstacleDecision od;
    od.obstacle = b.obstacle_id;
    od.dynamic = b.dynamic;
    const decision::Side side = decision::side_of(decision_.space(), d, b);
    od.lateral = side == decision::Side::kLeft ? LateralSide::kLeft
                 : side == decision::Side::kRight ? LateralSide::kRight
                                                  : LateralSide::kNone;
    static_cast<void>(out.decisions.push_back(od));
  }
  for (const StDecision& sd : st_.decisions()) {  // <= kMaxDynamicObstacles
    bool found = false;
    for (ObstacleDecision& od : out.decisions) {  // <= kMaxObstacles
      if (od.obstacle == sd.id && od.dynamic) {
        od.longitudinal = sd.decision;
        found = true;
      }
    }
    if (!found) {
      ObstacleDecision od;
      od.obstacle = sd.id;
      od.dynamic = true;
      od.longitudinal = sd.decision;
      static_cast<void>(out.decisions.push_back(od));
    }
  }
}

// A safe stop: brake at the comfortable limit along the previous plan's path
// if there is one, else along the current lateral offset of the reference
// line, else (no usable reference) straight ahead.
template <class Cfg>
void BasicPlanner<Cfg>::fallback(const Scene* scene, Scalar now, FallbackReason reason, Plan& out) {
  if (out.status != PlanStatus::kInvalidInput) {
    out.status = PlanStatus::kFallback;
    out.fallback = reason;
  }
  out.trajectory.clear();
  const bool have_state = scene != nullptr && finite_state(scene->ego.state);
  const Scalar v0 = have_state ? max_of(scene->ego.state.v, Scalar(0)) : Scalar(0);
  const bool on_previous = have_previous_ && previous_.trajectory.size() > 1 && now - previous_time_ >= 0 &&
                           now - previous_time_ < kFallbackPathAge && out.status != PlanStatus::kInvalidInput &&
                           have_state;
  const bool on_reference = !on_previous && have_state && reference_.valid() && out.status != PlanStatus::kInvalidInput;
  geometry::FrenetPoint f = on_reference ? reference_.to_frenet({scene->ego.state.x, scene->ego.state.y})
                                         : geometry::FrenetPoint{};
  // Hold the lateral offset of the first fallback cycle while fallbacks last,
  // instead of following an ego that drifts with its heading.
  if (on_reference) {
    if (!holding_fallback_l_) {
      fallback_l_ = f.l;
      holding_fallback_l_ = true;
    }
    f.l = fallback_l_;
  }
  // Where the ego is on the previous plan: its nearest sample.
  Scalar s_begin = 0;
  if (on_previous) {
    Scalar best = -1;
    for (const TrajectoryPoint& q : previous_.trajectory) {  // kTrajectorySamples
      const Scalar dx = q.x - scene->ego.state.x;
      const Scalar dy = q.y - scene->ego.state.y;
      const Scalar d2 = dx * dx + dy * dy;
      if (best < 0 || d2 < best) {
        best = d2;
        s_begin = q.s;
      }
    }
  }
  // Comfortable braking unless it runs into an obstacle on the way; then the
  // vehicle's hard limit (the shortest stop), unless that collides sooner
  // (e.g. with traffic closing in from behind): then comfortable after all.
  const Scalar hard = have_state && scene->ego.limits.a_min < settings_.comfort_decel ? scene->ego.limits.a_min
                                                                                      : settings_.comfort_decel;
  int comfortable_hit = -1;
  for (int attempt = 0; attempt < 3; ++attempt) {  // comfortable, hard, comfortable again
    const Scalar decel = attempt == 1 ? hard : settings_.comfort_decel;  // < 0
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
        // Walk the previous trajectory by arc length d from where the ego is now.
        const Scalar target = s_begin + d;
        const TrajectoryPoint* a = &previous_.trajectory[0];
        const TrajectoryPoint* b = &previous_.trajectory[0];
        for (std::size_t i = 1; i < previous_.trajectory.size(); ++i) {  // kTrajectorySamples
          b = &previous_.trajectory[i];
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
      } else if (on_reference) {
        const Scalar s = min_of(f.s + d, reference_.length());
        const geometry::CurveSample r = reference_.evaluate(s);
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
      static_cast<void>(out.trajectory.push_back(p));
    }
    if (!have_state || out.status == PlanStatus::kInvalidInput || attempt == 2) {
      break;
    }
    const int hit = first_collision(*scene, out, nullptr);
    if (hit < 0 || (attempt == 1 && hit >= comfortable_hit)) {
      break;
    }
    comfortable_hit = hit;
  }
}

// --- The iteration (paper §2) -------------------------------------------------

// A fingerprint of a decision's corridor as the path QP sees it: the
// bounds at its samples (to the millimetre). Within one cycle the path QP at
// the steering limit depends on nothing else (the start state is fixed), so a
// corridor that failed there fails again in a later iteration or round.
template <class Cfg>
std::uint64_t BasicPlanner<Cfg>::corridor_signature(const Decision& d, const PathInput& pi) const {
  constexpr std::uint64_t kFnvPrime = 1099511628211ull;
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a offset basis
  const int samples = Cfg::kPathBlocks * Cfg::kPathSamplesPerBlock;
  for (int k = 0; k <= samples; ++k) {  // the path QP's samples
    const Scalar s = pi.s0 + pi.length * static_cast<Scalar>(k) / static_cast<Scalar>(samples);
    const decision::LateralInterval c = decision::corridor_at(decision_.space(), d, s);
    const auto lo = static_cast<std::int64_t>(std::lround(c.lo * Scalar(1000)));
    const auto hi = static_cast<std::int64_t>(std::lround(c.hi * Scalar(1000)));
    h = (h ^ static_cast<std::uint64_t>(lo)) * kFnvPrime;
    h = (h ^ static_cast<std::uint64_t>(hi)) * kFnvPrime;
  }
  return h;
}

template <class Cfg>
bool BasicPlanner<Cfg>::known_infeasible(std::uint64_t corridor) const {
  for (const std::uint64_t c : infeasible_) {  // <= kRememberedInfeasibleCorridors
    if (c == corridor) {
      return true;
    }
  }
  return false;
}

// The track of the nearest moving obstacle whose SL box overlaps [s_lo, s_hi]
// in s and that is not yet left out; -1: none. Never one whose whole sweep
// is occupied (oncoming, or coming from behind in another lane): the ST graph
// cannot make the ego wait for those in their lane.
template <class Cfg>
int BasicPlanner<Cfg>::nearest_dynamic(std::size_t n_static, const bool* skip, Scalar s_lo,
                                       Scalar s_hi) const {
  int found = -1;
  Scalar nearest = Scalar(0);
  for (std::size_t i = n_static; i < boxes_.size(); ++i) {  // <= kMaxDynamicObstacles
    const decision::SlBox& b = boxes_[i];
    if (b.s_max < s_lo || b.s_min > s_hi || (found >= 0 && b.s_min >= nearest)) {
      continue;
    }
    for (int j = 0; j < track_count_; ++j) {  // <= kMaxDynamicObstacles
      const DynamicTrack& tr = tracks_[static_cast<std::size_t>(j)];
      if (tr.id == b.obstacle_id && !skip[j] && !tr.sweep_occupied) {
        found = j;
        nearest = b.s_min;
      }
    }
  }
  return found;
}

// Path s the ego's front bumper must stop before: the end of a blocked
// corridor (`reach`, a rear-axle position) or the end of the map, less the
// stop margin.
template <class Cfg>
Scalar BasicPlanner<Cfg>::stop_before(Scalar reach) const {
  return min_of(reach + front_, map_end_) - settings_.stop_margin;
}

// End of the slice that begins where a blocked corridor ends (`reach`).
template <class Cfg>
Scalar BasicPlanner<Cfg>::blocking_slice_end(Scalar reach) const {
  for (const decision::Slice& sl : decision_.space().slices) {  // <= kMaxSlices
    if (sl.s_begin >= reach) {
      return sl.s_end;
    }
  }
  return reach;
}

// Decision (1.1) and path QP (1.2). A moving obstacle is not a wall: when it
// blocks the best corridor, leaves no decision, or no path QP fits the
// corridors it shapes, it is left to the ST graph (follow or yield) and the
// stage runs again, one obstacle more per round. The path QP tries the
// decisions in cost order (the coarse QP only sees samples every few metres),
// each first with the curvature bound at the expected speed, then at the
// steering limit only (the speed stage then slows the ego for it).
template <class Cfg>
FallbackReason BasicPlanner<Cfg>::decide_path(const std::array<Scalar, Cfg::kStSamples>& s_guess,
                                              std::size_t n_static,
                                              const decision::ConvexSpaceParams& cp,
                                              const CoarseInput& ci, PathInput& pi, Plan& out) {
  bool skip[Cfg::kMaxDynamicObstacles] = {};
  chosen_ = -1;
  evasive_ = false;
  FallbackReason why = FallbackReason::kNoDecision;  // why the next round is needed
  for (int round = 0; round <= Cfg::kMaxDynamicObstacles; ++round) {  // one more left-out obstacle per round
    if (decision_runs_ >= Cfg::kMaxDecisionRunsPerCycle) {
      return why;  // budget spent: the worst case stays bounded (WCET), the caller falls back
    }
    ++decision_runs_;
    std::uint64_t t0 = ticks_.ticks();
    while (boxes_.size() > n_static) {  // drop last round's dynamic boxes
      boxes_.pop_back();
    }
    place_dynamic(s_guess, skip);
    const decision::DecisionStatus ds = decision_.run(road_, boxes_.span(), cp, ci, settings_.decision_weights);
    ++out.timing.decision_runs;
    for (std::size_t i = 0; i < decision_.decisions().kept.size(); ++i) {  // <= kKeptDecisions
      ++out.qp_solves;
      out.qp_iterations += decision_.coarse(i).qp_iterations;
    }
    out.timing.decision += ticks_.ticks() - t0;
    if (ds == decision::DecisionStatus::kInvalidInput) {
      return FallbackReason::kNoDecision;
    }
    int drop = -1;
    why = FallbackReason::kNoDecision;
    if (ds == decision::DecisionStatus::kNoDecision || decision_.best() < 0) {
      drop = nearest_dynamic(n_static, skip, -kEverywhere, kEverywhere);
      if (drop < 0) {
        return FallbackReason::kNoDecision;
      }
    } else if (ds == decision::DecisionStatus::kBlocked) {
      // The best corridor ends where the next slice has no zone it links to:
      // a moving obstacle in that slice is left to the ST graph; none there
      // means the ego waits (for traffic in its sweep) or static obstacles
      // block the road (a real stop).
      const Decision& best = decision_.decisions().kept[static_cast<std::size_t>(decision_.best())];
      drop = nearest_dynamic(n_static, skip, best.reach, blocking_slice_end(best.reach));
    }
    if (drop < 0) {
      t0 = ticks_.ticks();
      std::array<int, Cfg::kKeptDecisions> order{};
      const int candidates = rank_decisions(order);
      for (int attempt = 0; attempt < candidates && attempt < kMaxPathAttempts && chosen_ < 0; ++attempt) {
        const int index = order[static_cast<std::size_t>(attempt)];
        const Decision& d = decision_.decisions().kept[static_cast<std::size_t>(index)];
        const std::uint64_t corridor = corridor_signature(d, pi);
        if (known_infeasible(corridor)) {
          continue;  // this corridor failed at the steering limit earlier in this cycle
        }
        // The curvature bound at the expected speed, then at the slowest
        // speed braking can reach, then (the two best decisions only) the
        // same with the evasive lateral acceleration: a plan that needs it is
        // a fallback (evasive), the safest way out, not a stop where the ego
        // stands (in an oncoming lane, say). Within the cycle's budget.
        const int levels = attempt < kEvasiveAttempts ? 3 : 2;
        for (int relax = 0; relax < levels && chosen_ < 0 && path_solves_ < Cfg::kMaxPathSolvesPerCycle;
             ++relax) {
          ++path_solves_;
          pi.kappa_bound = relax == 0 ? &kappa_bound_ : (relax == 1 ? &kappa_reach_ : &kappa_evasive_);
          path_opt_.solve(decision_.space(), d, pi, settings_.path_weights, path_);
          ++out.qp_solves;
          out.qp_iterations += path_.iterations;
          if (qp::is_usable(path_.status)) {
            chosen_ = index;
            evasive_ = relax == 2;
          }
        }
        if (chosen_ < 0 && path_solves_ >= Cfg::kMaxPathSolvesPerCycle) {
          break;  // budget spent: the worst case stays bounded (WCET), the caller falls back
        }
        if (chosen_ < 0 && !infeasible_.full()) {
          static_cast<void>(infeasible_.push_back(corridor));
        }
      }
      out.timing.path += ticks_.ticks() - t0;
      if (chosen_ >= 0) {
        return FallbackReason::kNone;
      }
      drop = nearest_dynamic(n_static, skip, -kEverywhere, kEverywhere);
      if (drop < 0 || path_solves_ >= Cfg::kMaxPathSolvesPerCycle) {
        return FallbackReason::kPathQpFailed;
      }
      why = FallbackReason::kPathQpFailed;
    }
    skip[drop] = true;
  }
  return FallbackReason::kPathQpFailed;
}

// ST graph and speed QP along path_: with the braking the bounds need
// (bounds_.a_min), then, if that fails, with the vehicle's limit.
template <class Cfg>
void BasicPlanner<Cfg>::plan_speed(const StParams& stp, const StSamples& s_guess,
                                   const StSamples& v_guess, SpeedInput& si, Plan& out) {
  const std::span<const DynamicTrack> tracks(tracks_.data(), static_cast<std::size_t>(track_count_));
  st_.build(path_, tracks, stp, s_guess, v_guess, bounds_);
  si.a_min = bounds_.a_min;
  speed_opt_.solve(si, bounds_, settings_.speed_weights, speed_);
  ++out.qp_solves;
  out.qp_iterations += speed_.iterations;
  if (!qp::is_usable(speed_.status) && st_.kept_ahead()) {
    // Keeping ahead of a follower is a wish, not a constraint: without it.
    StParams without = stp;
    without.keep_ahead = false;
    st_.build(path_, tracks, without, s_guess, v_guess, bounds_);
    si.a_min = bounds_.a_min;
    speed_opt_.solve(si, bounds_, settings_.speed_weights, speed_);
    ++out.qp_solves;
    out.qp_iterations += speed_.iterations;
  }
  if (!qp::is_usable(speed_.status) && bounds_.a_min > limits_.a_min) {
    si.a_min = limits_.a_min;
    speed_opt_.solve(si, bounds_, settings_.speed_weights, speed_);
    ++out.qp_solves;
    out.qp_iterations += speed_.iterations;
  }
}

template <class Cfg>
bool BasicPlanner<Cfg>::iterate(const Scene& scene, const Start& start, Plan& out) {
  StSamples s_guess{};
  StSamples v_guess{};
  StParams stp;
  stp.s0 = start.s;
  stp.v0 = start.v;
  stp.a0 = start.a;
  stp.front = front_;
  stp.rear = rear_;
  stp.half_width = Scalar(0.5) * scene.ego.geometry.width;
  stp.limits = limits_;
  stp.comfort_decel = settings_.comfort_decel;
  stp.kappa_ref = &kappa_;
  stp.stop_s = stop_before(kEverywhere);
  stp.path_end = start.s + length_;
  update_kappa_reach(kappa_reach_, start.v, limits_.a_lat_max);
  update_kappa_reach(kappa_evasive_, start.v, max_of(limits_.a_lat_max, settings_.evasive_lat_acc));
  speed::reference_profile(stp, Cfg::kSpeedHorizon, s_guess, v_guess);  // step 0

  decision::ConvexSpaceParams cp;
  cp.s_start = start.s;
  cp.s_end = start.s + length_;
  cp.vehicle_width = scene.ego.geometry.width;
  cp.ego_l = start.l;
  CoarseInput ci;
  ci.l_init = start.l;
  ci.v_init = start.v;
  ci.l_ref = scene.road.target_lane_offset;
  ci.vehicle_width = scene.ego.geometry.width;
  ci.stop_margin = settings_.stop_margin;
  ci.limits = limits_;
  ci.kappa_ref = &kappa_;
  PathInput pi;
  pi.s0 = start.s;
  pi.length = length_;
  pi.l0 = start.l;
  pi.dl0 = start.dl;
  pi.ddl0 = start.ddl;
  pi.l_target = scene.road.target_lane_offset;
  pi.vehicle_width = scene.ego.geometry.width;
  pi.front_reach = front_;
  pi.rear_reach = rear_;
  pi.kappa_max = limits_.kappa_max;
  pi.kappa_ref = &kappa_;
  SpeedInput si;
  si.v0 = start.v;
  si.a0 = start.a;
  si.a_min = limits_.a_min;
  si.a_max = limits_.a_max;

  const std::size_t n_static = boxes_.size();
  StSamples last_s{};
  StSamples last_l{};
  StSamples last2_s{};  // two iterations back (a 2-cycle of the iteration)
  StSamples last2_l{};
  // Warm start: a stitched cycle starts the iteration from the previous
  // plan's motion (still in path_ and speed_), so a plan that still holds is
  // confirmed by the first iteration instead of re-derived from step 0.
  const bool warm = start.stitched_age >= 0;
  if (warm) {
    const Scalar age = start.stitched_age;
    const Scalar s_at = speed_.eval(age, 0);
    const Scalar t_end = Cfg::kSpeedHorizon;
    for (int k = 0; k < kSamples; ++k) {  // Cfg::kStSamples
      const auto u = static_cast<std::size_t>(k);
      const Scalar t = age + kDt * static_cast<Scalar>(k);
      const Scalar beyond = t > t_end ? t - t_end : Scalar(0);  // past the old horizon: its last speed
      s_guess[u] = speed_.eval(t, 0) + beyond * max_of(speed_.eval(t_end, 1), Scalar(0)) - s_at;
      v_guess[u] = max_of(speed_.eval(t, 1), Scalar(0));
      last_s[u] = s_guess[u];
      last_l[u] = path_.eval(start.s + s_guess[u], 0);
    }
  } else if (!have_previous_) {
    // First cycle: accelerating to the speed limit puts the ego far ahead of
    // where a leader or the road's curvature lets it be, so the first
    // iteration met the moving obstacles at the wrong places and two more were
    // needed to settle. The step-0 guess is a speed plan instead: ST graph and
    // speed QP along the lane the ego is in (l = init_sl's l; path_ holds it
    // until the path QP). First cycles of the envelope scenes: 3.1 -> 2.4 iterations.
    // Not after a fallback: there the iteration from this guess could settle on
    // plans that keep colliding (a truth-prediction scene stopped in the way of
    // a car from behind), which the reference-profile guess avoids.
    const std::uint64_t t0 = ticks_.ticks();
    path_ = PathResult{};
    path_.status = qp::QpStatus::kOptimal;
    path_.s0 = start.s;
    path_.h = length_ / static_cast<Scalar>(Cfg::kPathBlocks);
    for (int b = 0; b < Cfg::kPathBlocks; ++b) {  // kPathBlocks: l(s) = l0 in every block
      path_.coefficients[static_cast<std::size_t>(6 * b)] = start.l;
    }
    plan_speed(stp, s_guess, v_guess, si, out);
    if (qp::is_usable(speed_.status)) {
      for (int k = 0; k < kSamples; ++k) {  // Cfg::kStSamples
        const auto u = static_cast<std::size_t>(k);
        s_guess[u] = speed_.eval(kDt * static_cast<Scalar>(k), 0);
        v_guess[u] = speed_.eval(kDt * static_cast<Scalar>(k), 1);
      }
    }
    out.timing.speed += ticks_.ticks() - t0;
  }
  bool safe = false;
  for (int iter = 0; iter < Cfg::kMaxPlannerIterations; ++iter) {  // the paper's iteration
    out.iterations = iter + 1;
    // 1.1 + 1.2: convex space, decision and path QP, with dynamic obstacles at
    // their meeting places.
    update_kappa_bound(s_guess, v_guess);
    const FallbackReason why = decide_path(s_guess, n_static, cp, ci, pi, out);
    if (why != FallbackReason::kNone) {
      fallback(&scene, now_, why, out);
      return false;
    }
    const Decision& chosen = decision_.decisions().kept[static_cast<std::size_t>(chosen_)];
    blocked_ = !chosen.reaches_end;
    // Blocked by static obstacles alone (a stop, reported as a fallback), or
    // waiting for moving traffic that will clear (an ok plan).
    blocked_by_statics_ =
        blocked_ && decision::widest_free_gap(road_, boxes_.span().first(n_static), chosen.reach,
                                              blocking_slice_end(chosen.reach)) <
                        scene.ego.geometry.width;

    // 1.3 ST graph and speed QP along the path. A stop before static
    // obstacles is a fallback: it brakes only, never speeds up on the way.
    si.a_max = blocked_by_statics_ ? Scalar(0) : limits_.a_max;
    std::uint64_t t0 = ticks_.ticks();
    stp.stop_s = stop_before(blocked_ ? chosen.reach : kEverywhere);
    plan_speed(stp, s_guess, v_guess, si, out);
    if (!qp::is_usable(speed_.status)) {
      // Retry once conservatively: yield instead of overtaking, and the
      // curvature speed limit over every reachable position.
      stp.conservative = true;
      plan_speed(stp, s_guess, v_guess, si, out);
      stp.conservative = false;
    }
    out.timing.speed += ticks_.ticks() - t0;
    if (!qp::is_usable(speed_.status)) {
      fallback(&scene, now_, FallbackReason::kSpeedQpFailed, out);
      return false;
    }

    // Check with the real footprints, and measure the change from the last step.
    t0 = ticks_.ticks();
    sample_trajectory(start, out);
    std::int32_t hit_id = -1;
    const int hit = first_collision(scene, out, &hit_id);
    safe = hit < 0;
    out.collision_obstacle = hit_id;
    out.collision_time = safe ? Scalar(-1) : out.trajectory[static_cast<std::size_t>(hit)].t;
    Scalar change_s = 0;
    Scalar change_l = 0;
    Scalar change2_s = 0;
    Scalar change2_l = 0;
    for (int k = 0; k < kSamples; ++k) {  // Cfg::kStSamples
      const auto u = static_cast<std::size_t>(k);
      const Scalar s = speed_.eval(kDt * static_cast<Scalar>(k), 0);
      const Scalar l = out.trajectory[u].l;
      change_s = max_of(change_s, std::fabs(s - last_s[u]));
      change_l = max_of(change_l, std::fabs(l - last_l[u]));
      change2_s = max_of(change2_s, std::fabs(s - last2_s[u]));
      change2_l = max_of(change2_l, std::fabs(l - last2_l[u]));
      last2_s[u] = last_s[u];
      last2_l[u] = last_l[u];
      last_s[u] = s;
      last_l[u] = l;
      s_guess[u] = s;
      v_guess[u] = speed_.eval(kDt * static_cast<Scalar>(k), 1);
    }
    out.timing.check += ticks_.ticks() - t0;
    const bool converged = (iter > 0 || warm) && change_s < settings_.converge_s && change_l < settings_.converge_l;
    if (safe && converged) {
      break;
    }
    // A 2-cycle (this result within the thresholds of the one two iterations
    // back): the remaining iterations would only alternate, and the last one
    // would return this result again when it has the same parity.
    const bool cycling = iter >= 2 && (Cfg::kMaxPlannerIterations - 1 - iter) % 2 == 0 &&
                         change2_s < settings_.converge_s && change2_l < settings_.converge_l;
    if (safe && cycling) {
      break;
    }
    if (blocked_ && safe && iter > 0) {
      break;
    }
  }
  if (!safe) {
    fallback(&scene, now_, FallbackReason::kCollision, out);
    return false;
  }
  record_decisions(out);
  if (evasive_) {
    // The only collision-free plan found needs more lateral acceleration than
    // lat_acc_max: a way out, reported as a fallback.
    out.status = PlanStatus::kFallback;
    out.fallback = FallbackReason::kEvasive;
    return false;
  }
  if (blocked_by_statics_) {
    // No corridor passes the static obstacles: the optimised trajectory is a
    // stop before them, reported as a fallback.
    out.status = PlanStatus::kFallback;
    out.fallback = FallbackReason::kBlocked;
    return false;
  }
  out.status = PlanStatus::kOk;
  out.fallback = FallbackReason::kNone;
  return true;
}

template <class Cfg>
void BasicPlanner<Cfg>::reset() {
  have_previous_ = false;
  last_cycle_ok_ = false;
  holding_fallback_l_ = false;
  decision_.reset();
  path_opt_.reset();
  speed_opt_.reset();
}

template <class Cfg>
PlanStatus BasicPlanner<Cfg>::plan(const PlanRequest& request, Plan& out) {
  const std::uint64_t t_begin = ticks_.ticks();
  out = Plan{};
  out.timing.tick_hz = ticks_.hz;
  chosen_ = -1;
  infeasible_.clear();
  path_solves_ = 0;
  decision_runs_ = 0;
  if (request.scene == nullptr) {
    out.status = PlanStatus::kInvalidInput;
    fallback(nullptr, request.now, FallbackReason::kNone, out);
    return out.status;
  }
  const Scene& scene = *request.scene;
  now_ = request.now;
  const bool prepared = prepare(scene, request.now, out);
  out.timing.prepare = ticks_.ticks() - t_begin;
  if (!prepared) {
    fallback(&scene, request.now, out.status == PlanStatus::kInvalidInput ? FallbackReason::kNone
                                                                         : FallbackReason::kHorizonTooShort, out);
  } else {
    const Start start = start_state(scene, request.now);
    iterate(scene, start, out);
  }
  out.timing.total = ticks_.ticks() - t_begin;
  // The last ok plan stays for stitching, hysteresis and the fallback's path;
  // a fallback does not erase it (it ages out instead).
  if (out.status == PlanStatus::kOk) {
    previous_ = out;
    previous_time_ = request.now;
    have_previous_ = true;
    holding_fallback_l_ = false;
  }
  last_cycle_ok_ = out.status == PlanStatus::kOk;
  return out.status;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C) template class BasicPlanner<C>;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::planner
