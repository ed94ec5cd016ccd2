#include "itp/speed/st_graph.hpp"

#include <cmath>
#include <limits>

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"
#include "itp/speed/braking.hpp"
#include "itp/speed/keep_ahead.hpp"
#include "itp/speed/path_footprint.hpp"

namespace itp::speed {
namespace {

constexpr int kReachProbes = 24;                 // conservative retry: positions probed per sample
constexpr Scalar kMovingAlong = Scalar(0.5);     // [m/s] slower is not "moving along the path"
template <class Cfg>
constexpr Scalar kDt = Cfg::kSpeedHorizon / static_cast<Scalar>(Cfg::kSpeedSamples);  // [s]
// [m] a guess this close to the follow limit is on it: a speed QP's solution
// sits on its active bound, so the strict test flipped on rounding.
constexpr Scalar kOnLimit = Scalar(1e-6);


// The braking the plan may use: comfortable when braking at comfort_decel
// (after kBrakeOnset) keeps every upper bound, else the least constant
// deceleration that does (bisection), with a margin for the spline's
// smoothness, at most the vehicle's limit. Without it the cost's pull
// towards s_up braked late at the vehicle's limit where less would do.
template <class Cfg>
Scalar braking_allowed(const BasicStParams<Cfg>& p, const BasicSpeedBounds<Cfg>& b) {
  constexpr int kBisections = 24;
  constexpr Scalar kMargin = Scalar(1.2);       // x the least deceleration
  constexpr Scalar kExtra = Scalar(0.3);        // [m/s^2] and this much more
  constexpr Scalar kTolerance = Scalar(0.005);  // [m]
  const Scalar v0 = max_of(p.v0, Scalar(0));
  constexpr Scalar kSpeedTolerance = Scalar(0.01);  // [m/s]
  const auto keeps_bounds = [&](Scalar decel) {  // decel < 0
    for (int k = 1; k < Cfg::kStSamples; ++k) {  // Cfg::kStSamples
      const auto u = static_cast<std::size_t>(k);
      const Scalar t = kDt<Cfg> * static_cast<Scalar>(k);
      // The speed bound too: braking now is the slowest motion, so where its
      // speed is above v_hi no motion meets it (a stop's or a follow's speed
      // condition is set at the guessed positions and can fall faster than
      // comfortable braking). Asking for comfort there made the speed QP
      // infeasible, certified only after tens of iterations, before the
      // retry at the vehicle's limit.
      const Scalar v = max_of(v0 + decel * max_of(t - kBrakeOnset, Scalar(0)), Scalar(0));
      if (braking_distance(v0, decel, t) > b.s_hi[u] + kTolerance || v > b.v_hi[u] + kSpeedTolerance) {
        return false;
      }
    }
    return true;
  };
  const Scalar hard = p.limits.a_min;
  const Scalar comfort = max_of(p.comfort_decel, hard);
  if (keeps_bounds(comfort)) {
    return comfort;
  }
  Scalar lo = comfort;  // too gentle
  Scalar hi = hard;     // enough (the bounds were floored at it)
  for (int i = 0; i < kBisections; ++i) {  // kBisections
    const Scalar mid = Scalar(0.5) * (lo + hi);
    if (keeps_bounds(mid)) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  return max_of(hard, hi * kMargin - kExtra);
}

// Picks the decision from where the ego is expected to be (s_guess, v_guess)
// when the obstacle first meets the swept path (t1).
template <class Cfg>
void classify(BasicStDecision<Cfg>& d, const BasicStParams<Cfg>& p,
              const std::array<Scalar, Cfg::kStSamples>& s_guess,
              const std::array<Scalar, Cfg::kStSamples>& v_guess) {
  if (d.k1 < 0) {
    d.decision = Longitudinal::kIgnore;
    return;
  }
  const auto u1 = static_cast<std::size_t>(d.k1);
  const Scalar ego = s_guess[u1];
  // A faster obstacle that meets the path behind the ego (its centre behind
  // the ego's) closes in from behind: the gap is the follower's to keep
  // (RSS). Neither yield to it (braking to let it pass through the ego is
  // what gets the ego rear-ended) nor make way for it.
  d.behind = Scalar(0.5) * (d.s_lo[u1] + d.s_hi[u1]) < ego;
  if (d.behind && d.speed[u1] > v_guess[u1]) {
    d.decision = Longitudinal::kIgnore;
    d.follower = true;
    return;
  }
  if (ego >= d.s_hi[u1]) {
    // The ego is past the conflict zone when it is entered: stay ahead (15),
    // unless the obstacle is the faster one, closing in from behind.
    d.follower = d.speed[u1] > v_guess[u1];
    d.decision = d.follower ? Longitudinal::kIgnore : Longitudinal::kOvertake;
    return;
  }
  // A leader moving along the path is followed at a safe gap for as long as
  // it is on the path (also when the path leaves it later: a yield would
  // tail it 2 m behind until then).
  const bool moving_along = d.speed[u1] > kMovingAlong;
  if (moving_along && d.s_lo[u1] > 0) {
    d.decision = Longitudinal::kFollow;
    return;
  }
  // Behind it, or inside the zone in the guess: yield if braking can make it.
  const Scalar v0 = max_of(p.v0, Scalar(0));
  const Scalar brake = v0 * v0 / (Scalar(-2) * p.limits.a_min);
  d.decision = d.s_lo[u1] >= brake || ego <= d.s_lo[u1] ? Longitudinal::kYield : Longitudinal::kOvertake;
}

// The gap a follow keeps at sample u (front bumper to the leader's SL box):
// the desired time gap, and never less than RSS's safe distance at the
// guessed speed. When the gap is already short where the leader enters the
// path (t1: a cut-in), the desired one is reached at gap_recovery_rate, so
// the ego eases off instead of braking at its limit to restore it at once.
template <class Cfg>
Scalar follow_gap(const BasicStDecision<Cfg>& d, const BasicStParams<Cfg>& p,
                  const std::array<Scalar, Cfg::kStSamples>& s_guess,
                  const std::array<Scalar, Cfg::kStSamples>& v_guess, int k) {
  const auto u = static_cast<std::size_t>(k);
  const Scalar v_obj = max_of(d.speed[u], Scalar(0));
  const Scalar safe = p.rss.distance(max_of(v_guess[u], Scalar(0)), v_obj);
  const Scalar desired = max_of(p.follow_distance + p.follow_time_gap * v_obj, safe);
  const auto u1 = static_cast<std::size_t>(d.k1);
  const Scalar gap1 = d.s_lo[u1] + p.longitudinal_margin - s_guess[u1];  // where it enters
  const Scalar recovered = gap1 + p.gap_recovery_rate * kDt<Cfg> * static_cast<Scalar>(k - d.k1);
  return max_of(safe, min_of(desired, recovered));
}

// Tightens the speed QP's bounds by one obstacle's decision (eq. 15-17).
template <class Cfg>
void apply(const BasicStDecision<Cfg>& d, const BasicStParams<Cfg>& p,
           const std::array<Scalar, Cfg::kStSamples>& s_guess,
           const std::array<Scalar, Cfg::kStSamples>& v_guess, BasicSpeedBounds<Cfg>& b) {
  for (int k = d.k1; d.decision != Longitudinal::kIgnore && k <= d.k2; ++k) {  // <= Cfg::kStSamples
    const auto u = static_cast<std::size_t>(k);
    if (!d.conflict[u]) {
      continue;
    }
    switch (d.decision) {
      case Longitudinal::kYield:
        b.s_hi[u] = min_of(b.s_hi[u], d.s_lo[u]);
        break;
      case Longitudinal::kFollow: {
        // (17): behind by a time gap, and no faster than the leader once the
        // gap is used up; faster only by what braking can still take back.
        const Scalar v_obj = max_of(d.speed[u], Scalar(0));
        const Scalar limit = d.s_lo[u] + p.longitudinal_margin - follow_gap(d, p, s_guess, v_guess, k);
        b.s_hi[u] = min_of(b.s_hi[u], limit);
        // The speed condition needs a consistent guess (behind the limit);
        // a too optimistic one (step 0) leaves the s bound alone to act.
        if (s_guess[u] <= limit + kOnLimit) {
          const Scalar room = max_of(limit - s_guess[u], Scalar(0));
          b.v_hi[u] = min_of(b.v_hi[u], v_obj + std::sqrt(Scalar(-2) * p.limits.a_min * room));
        }
        b.v_ref[u] = min_of(b.v_ref[u], v_obj);
        break;
      }
      case Longitudinal::kOvertake:
        b.s_lo[u] = max_of(b.s_lo[u], d.s_hi[u]);
        b.v_lo[u] = max_of(b.v_lo[u], min_of(d.speed[u], b.v_hi[u]));
        break;
      case Longitudinal::kIgnore:
        break;
    }
  }
}

}  // namespace

const char* to_string(Longitudinal decision) {
  switch (decision) {
    case Longitudinal::kIgnore: return "ignore";
    case Longitudinal::kYield: return "yield";
    case Longitudinal::kFollow: return "follow";
    case Longitudinal::kOvertake: return "overtake";
  }
  return "unknown";
}

template <class Cfg>
void reference_profile(const BasicStParams<Cfg>& p, Scalar horizon,
                       std::array<Scalar, Cfg::kStSamples>& s_ref,
                       std::array<Scalar, Cfg::kStSamples>& v_ref) {
  const Scalar dt = horizon / static_cast<Scalar>(Cfg::kSpeedSamples);
  Scalar s = 0;
  Scalar v = max_of(p.v0, Scalar(0));
  for (int k = 0; k < Cfg::kStSamples; ++k) {  // Cfg::kStSamples
    const Scalar lim = decision::curve_speed_limit(
        p.limits, p.kappa_ref != nullptr ? p.kappa_ref->at(p.s0 + s) : Scalar(0));
    s_ref[static_cast<std::size_t>(k)] = s;
    v_ref[static_cast<std::size_t>(k)] = v;
    const Scalar v_next = v < lim ? min_of(lim, v + p.limits.a_max * dt) : max_of(lim, v + p.limits.a_min * dt);
    s += Scalar(0.5) * (v + v_next) * dt;
    v = v_next;
  }
}

template <class Cfg>
void BasicStGraph<Cfg>::build(const PathResult& path, std::span<const DynamicTrack> tracks,
                              const StParams& p, const std::array<Scalar, Cfg::kStSamples>& s_guess,
                              const std::array<Scalar, Cfg::kStSamples>& v_guess, SpeedBounds& b) {
  const Scalar inf = std::numeric_limits<Scalar>::infinity();
  decisions_.clear();
  LateralRange<Cfg> range;
  lateral_range(path, range);
  // s_up: the furthest the ego could be, as the paper's "as fast as allowed".
  std::array<Scalar, Cfg::kStSamples> s_ref{};
  std::array<Scalar, Cfg::kStSamples> v_ref{};
  reference_profile(p, Cfg::kSpeedHorizon, s_ref, v_ref);
  // The road: speed limit along the path at the guessed positions (or, in
  // the conservative retry, the lowest over the reachable range).
  for (int k = 0; k < Cfg::kStSamples; ++k) {  // Cfg::kStSamples
    const auto u = static_cast<std::size_t>(k);
    b.s_lo[u] = 0;
    b.s_hi[u] = inf;
    b.v_lo[u] = 0;
    b.v_hi[u] = speed_limit_at(path, p, p.s0 + s_guess[u]);
    if (p.conservative) {
      const Scalar t = kDt<Cfg> * static_cast<Scalar>(k);
      const Scalar lo = braking_distance(max_of(p.v0, Scalar(0)), p.limits.a_min, t);
      for (int j = 0; j <= kReachProbes; ++j) {  // kReachProbes + 1 positions
        const Scalar s = lo + (s_ref[u] - lo) * static_cast<Scalar>(j) / static_cast<Scalar>(kReachProbes);
        b.v_hi[u] = min_of(b.v_hi[u], speed_limit_at(path, p, p.s0 + s));
      }
    }
    b.v_ref[u] = b.v_hi[u];
  }
  for (int k = 0; k < Cfg::kStSamples; ++k) {  // Cfg::kStSamples
    b.s_ref[static_cast<std::size_t>(k)] = s_ref[static_cast<std::size_t>(k)];
  }
  if (p.path_end >= 0) {
    for (auto& s : b.s_hi) {  // Cfg::kStSamples
      s = min_of(s, p.path_end - p.s0 - p.front);
    }
  }
  // The front bumper stays before stop_s (a blocked corridor, the map's end).
  // And it can still stop there: the speed at a guessed position is at most
  // what braking at a_min takes back over the room left (as for a follow).
  if (p.stop_s >= 0) {
    const Scalar limit = p.stop_s - p.s0 - p.front;
    for (int k = 0; k < Cfg::kStSamples; ++k) {  // Cfg::kStSamples
      const auto u = static_cast<std::size_t>(k);
      b.s_hi[u] = min_of(b.s_hi[u], limit);
      if (s_guess[u] <= limit + kOnLimit) {
        const Scalar room = max_of(limit - s_guess[u], Scalar(0));
        b.v_hi[u] = min_of(b.v_hi[u], std::sqrt(Scalar(-2) * p.limits.a_min * room));
      }
    }
  }
  for (const DynamicTrack& tr : tracks) {  // <= kMaxDynamicObstacles
    StDecision d;
    d.id = tr.id;
    // A sweep-occupied obstacle (oncoming, from behind) is a wall of the
    // convex space over everything it covers: the path's corridor already
    // keeps the ego's body out of its (margin-inflated) boxes, so the swept
    // path is tested with no margin on top. With the margin, a path that
    // keeps its lane on a narrow two-way road met every oncoming car in its
    // own lane, and the ego braked at its limit to "yield" to it.
    const Scalar lateral_margin = tr.sweep_occupied ? Scalar(0) : p.lateral_margin;
    Scalar prev_center = 0;
    bool have_prev = false;
    for (int k = 0; k < Cfg::kStSamples; ++k) {  // Cfg::kStSamples
      const auto u = static_cast<std::size_t>(k);
      if (!tr.present[u]) {
        have_prev = false;
        continue;
      }
      const decision::SlBox& box = tr.box[u];
      const Scalar center = Scalar(0.5) * (box.s_min + box.s_max);
      d.speed[u] = have_prev ? (center - prev_center) / kDt<Cfg> : Scalar(0);
      prev_center = center;
      have_prev = true;
      if (path_conflicts(path, range, p, box, lateral_margin)) {
        d.conflict[u] = true;
        d.s_lo[u] = box.s_min - p.s0 - p.front - p.longitudinal_margin;
        d.s_hi[u] = box.s_max - p.s0 + p.rear + p.longitudinal_margin;
        d.k1 = d.k1 < 0 ? k : d.k1;
        d.k2 = k;
      }
    }
    if (d.k1 >= 0 &&
        d.k1 + 1 < Cfg::kStSamples) {  // speed at t1 from the next sample when t1 is the first
      const auto u1 = static_cast<std::size_t>(d.k1);
      if (d.speed[u1] == 0 && tr.present[u1 + 1]) {
        d.speed[u1] = d.speed[u1 + 1];
      }
    }
    classify(d, p, s_guess, v_guess);
    if (p.conservative && d.decision == Longitudinal::kOvertake) {
      d.decision = d.behind ? Longitudinal::kIgnore : Longitudinal::kYield;
    }
    // Cleared above; one per track <= kMaxDynamicObstacles = capacity.
    static_cast<void>(decisions_.push_back(d));
  }
  // Upper bounds first (yield, follow), then overtakes, each only if it is
  // consistent with them and reachable at full acceleration (s_ref); an
  // overtake that is not becomes a yield. Two passes over <= kMaxDynamicObstacles.
  for (StDecision& d : decisions_) {
    if (d.decision == Longitudinal::kYield || d.decision == Longitudinal::kFollow) {
      apply(d, p, s_guess, v_guess, b);
    }
  }
  for (StDecision& d : decisions_) {
    if (d.decision != Longitudinal::kOvertake) {
      continue;
    }
    bool feasible = true;
    for (int k = d.k1; k <= d.k2; ++k) {  // <= Cfg::kStSamples
      const auto u = static_cast<std::size_t>(k);
      if (d.conflict[u] && d.s_hi[u] > min_of(b.s_hi[u], s_ref[u]) - p.longitudinal_margin) {
        feasible = false;
      }
    }
    if (!feasible) {
      // Never yield to what is behind the ego at t1: staying behind it means
      // letting it drive through the ego. A follower then (keep ahead of it
      // as far as braking for what lies ahead allows).
      d.follower = d.behind;
      d.decision = d.behind ? Longitudinal::kIgnore : Longitudinal::kYield;
    }
    apply(d, p, s_guess, v_guess, b);
  }
  kept_ahead_ = false;
  bool any_follower = false;
  for (const StDecision& d : decisions_) {  // <= kMaxDynamicObstacles
    any_follower = any_follower || d.follower;
  }
  if (p.keep_ahead && !p.conservative && any_follower) {
    // Keep ahead of followers no further than the latest comfortable braking
    // that keeps every upper bound (a motion the speed QP can drive); none
    // when braking now is already too late for comfort.
    constexpr Scalar kTolerance = Scalar(0.005);  // [m]
    const Scalar path_limit = p.path_end >= 0 ? p.path_end - p.s0 - p.front : inf;
    const Scalar decel = max_of(p.comfort_decel, p.limits.a_min);
    const int m = latest_braking(p, b, decel, path_limit, kTolerance);
    for (std::size_t i = 0; i < decisions_.size() && m >= 0; ++i) {  // <= kMaxDynamicObstacles
      if (decisions_[i].follower && keep_ahead(decisions_[i], tracks[i], path, p, m, decel, b)) {
        kept_ahead_ = true;
      }
    }
  }
  // Never ask for less than full braking can give: keep s_hi reachable (a
  // collision that braking cannot avoid is caught by the collision check).
  for (int k = 0; k < Cfg::kStSamples; ++k) {  // Cfg::kStSamples
    const auto u = static_cast<std::size_t>(k);
    const Scalar t = kDt<Cfg> * static_cast<Scalar>(k);
    const Scalar v0 = max_of(p.v0, Scalar(0));
    const Scalar s_min = braking_distance(v0, p.limits.a_min, t);
    const Scalar v_min = max_of(v0 + p.limits.a_min * max_of(t - kBrakeOnset, Scalar(0)), Scalar(0));
    b.s_hi[u] = max_of(b.s_hi[u], s_min + Scalar(0.01));
    b.s_lo[u] = min_of(b.s_lo[u], b.s_hi[u]);
    b.v_hi[u] = max_of(max_of(b.v_hi[u], b.v_lo[u]), v_min + Scalar(0.01));
  }
  b.a_min = braking_allowed(p, b);
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                               \
  template class BasicStGraph<C>;                                        \
  template void reference_profile<C>(const BasicStParams<C>&, Scalar,    \
                                     std::array<Scalar, C::kStSamples>&, \
                                     std::array<Scalar, C::kStSamples>&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::speed
