#pragma once
// Paper 1.3, the ST graph: where and when each dynamic obstacle's predicted
// footprint meets the ego's swept path, the per-obstacle decision (yield,
// follow, overtake; eq. 15-17) and the bounds and references of the speed QP.
//
// Speed-QP s is the distance travelled along the path from the ego's current
// position: path s = s0 + s. The ego's rear axle is its reference point, so an
// obstacle occupying path s in [a, b] forbids the rear axle from
// [a - front, b + rear] (front: rear axle to front bumper, rear: rear overhang).
#include <array>
#include <cstdint>

#include "itp/config.hpp"
#include "itp/core/static_vector.hpp"
#include "itp/decision/convex_space.hpp"
#include "itp/decision/curvature_profile.hpp"
#include "itp/decision/motion_limits.hpp"
#include "itp/path/path_optimizer.hpp"
#include "itp/speed/speed_optimizer.hpp"

namespace itp::speed {

// A dynamic obstacle's predicted SL footprint at every speed sample
// (t_k = k * horizon / Cfg::kSpeedSamples, k = 0..kSpeedSamples).
template <class Cfg>
struct BasicDynamicTrack {
  std::int32_t id = 0;
  std::array<decision::SlBox, Cfg::kStSamples> box{};
  std::array<bool, Cfg::kStSamples> present{};  // false before it appears
  // Oncoming, or first seen behind the ego: the path treats everything it
  // covers over the horizon as occupied (planner, place_dynamic).
  bool sweep_occupied = false;
  // ... for the second reason: traffic from behind in another lane than the
  // ego's target lane (where it moves into the target lane, a follower there).
  bool from_behind = false;
  // First seen behind the ego in the ego's (target) lane, moving its way,
  // with the ego in that lane: it can meet the ego only by running into it
  // from behind, which is its business (RSS); never a wall in the convex
  // space (a lateral decision around it swerved the ego out of its lane).
  bool follower = false;
  // Crossing the road (or its sweep leaves no passage): never a wall in the
  // convex space, only the ST graph's (yield); planner, project_obstacles.
  bool crossing = false;
};

enum class Longitudinal : std::uint8_t {
  kIgnore = 0,  // never meets the path, or only behind the ego
  kYield,       // stay behind the conflict zone while the obstacle is in it (16)
  kFollow,      // stay a time gap behind and no faster (17)
  kOvertake,    // stay ahead of it and no slower (15)
};

const char* to_string(Longitudinal decision);

template <class Cfg>
struct BasicStDecision {
  std::int32_t id = 0;
  Longitudinal decision = Longitudinal::kIgnore;
  int k1 = -1;  // first conflicting sample (t1)
  int k2 = -1;  // last conflicting sample (t2)
  std::array<bool, Cfg::kStSamples> conflict{};  // the footprint meets the swept path at t_k
  std::array<Scalar, Cfg::kStSamples>
      s_lo{};  // [m] forbidden interval of the ego's speed-s, when in conflict
  std::array<Scalar, Cfg::kStSamples> s_hi{};
  std::array<Scalar, Cfg::kStSamples> speed{};  // [m/s] obstacle's speed along the path
  // Ignored because it closes in from behind (a follower): the ego keeps
  // ahead of it where it is in line with the path and braking allows.
  bool follower = false;
  bool behind = false;  // its centre behind the ego's (guessed) one at t1
};

// The safe following distance of RSS (Shalev-Shwartz et al., "On a Formal
// Model of Safe and Scalable Self-driving Cars", 2017): the ego, reacting
// after `reaction_time` and then braking at `ego_brake`, stops behind a
// leader that brakes at `leader_brake` at any moment, whatever the
// prediction says:
//   d = v_e rho + v_e^2 / (2 b_e) - v_l^2 / (2 b_l) + min_gap.
// The ego's planning cycle (0.1 s) and the tracking controller's lag are
// inside rho; b_e is below the vehicle's limit (-6 m/s^2 by default) so that
// the response is firm, not an emergency; 8 m/s^2 is a car's full braking on
// a dry road.
struct RssFollow {
  Scalar reaction_time = Scalar(0.5);  // [s] rho
  Scalar ego_brake = Scalar(4.0);      // [m/s^2] b_e > 0
  Scalar leader_brake = Scalar(8.0);   // [m/s^2] b_l > 0
  Scalar min_gap = Scalar(2.0);        // [m] left at standstill

  Scalar distance(Scalar v_ego, Scalar v_leader) const {
    const Scalar d = v_ego * reaction_time + v_ego * v_ego / (Scalar(2) * ego_brake) -
                     v_leader * v_leader / (Scalar(2) * leader_brake);
    return (d > 0 ? d : Scalar(0)) + min_gap;
  }
};

template <class Cfg>
struct BasicStParams {
  Scalar s0 = 0;                     // [m] path s of the ego
  Scalar v0 = 0;                     // [m/s]
  Scalar a0 = 0;                     // [m/s^2]
  Scalar front = Scalar(3.8);        // [m] rear axle to front bumper
  Scalar rear = Scalar(1.0);         // [m] rear overhang
  Scalar half_width = Scalar(0.95);  // [m] ego half width
  Scalar lateral_margin = Scalar(0.3);   // [m] swept-path inflation for conflicts
  Scalar longitudinal_margin = Scalar(2.0);  // [m] kept from a conflict zone
  Scalar follow_distance = Scalar(4.0);  // [m] standstill gap when following
  Scalar follow_time_gap = Scalar(1.2);  // [s] extra gap per m/s of the leader
  // A gap below the desired one (a cut-in) is restored at this rate, not at
  // once by braking at the limit; never below the safe gap (RssFollow).
  Scalar gap_recovery_rate = Scalar(2.0);  // [m/s]
  RssFollow rss{};
  Scalar stop_s = -1;  // [m] path s the ego's front must stop before (blocked corridor, end of the map); < 0: none
  // [m] path s the front stays behind: the end of the planned path (the speed
  // plan never runs past the path it follows; not a wall: no stop needed); < 0: none
  Scalar path_end = -1;
  decision::MotionLimits limits;  // a_min: the vehicle's hard braking limit
  Scalar comfort_decel = Scalar(-3);  // [m/s^2] braking a plan uses when that is enough
  // The retry when the speed QP was infeasible: every overtake becomes a yield
  // and the curvature speed limit at t is the lowest over every position the
  // ego can reach by t (not just the guessed one).
  bool conservative = false;
  // Keep ahead of followers (StDecision::follower) while comfortable braking
  // still meets every upper bound: no braking earlier than what lies ahead
  // needs when traffic closes in from behind. Off in the conservative retry,
  // and in the retry when the speed QP fails with it.
  bool keep_ahead = true;
  const decision::BasicCurvatureProfile<Cfg>* kappa_ref = nullptr;
};

template <class Cfg>
class BasicStGraph {
 public:
  using DynamicTrack = BasicDynamicTrack<Cfg>;
  using StDecision = BasicStDecision<Cfg>;
  using StParams = BasicStParams<Cfg>;
  using SpeedBounds = BasicSpeedBounds<Cfg>;
  using PathResult = path::BasicPathResult<Cfg>;

  // `s_guess[k]`, `v_guess[k]`: the ego's speed-s and speed at t_k from the
  // previous iteration (or the reference profile at step 0); they pick the
  // decisions and the curvature speed limit. Fills `bounds` for the speed QP.
  void build(const PathResult& path, std::span<const DynamicTrack> tracks, const StParams& params,
             const std::array<Scalar, Cfg::kStSamples>& s_guess,
             const std::array<Scalar, Cfg::kStSamples>& v_guess, SpeedBounds& bounds);

  const StaticVector<StDecision, Cfg::kMaxDynamicObstacles>& decisions() const {
    return decisions_;
  }
  // The last build raised a lower bound to keep ahead of a follower.
  bool kept_ahead() const { return kept_ahead_; }

 private:
  StaticVector<StDecision, Cfg::kMaxDynamicObstacles> decisions_;
  bool kept_ahead_ = false;
};

// The reference profile: from v0, accelerate at a_max (or brake at a_min) towards
// the speed limit, with lateral acceleration on κ_ref along the way. Its s and
// speed at the samples: s_up of the cost, and the step-0 guess of the iteration.
template <class Cfg>
void reference_profile(const BasicStParams<Cfg>& params, Scalar horizon,
                       std::array<Scalar, Cfg::kStSamples>& s_ref,
                       std::array<Scalar, Cfg::kStSamples>& v_ref);

using DynamicTrack = BasicDynamicTrack<DefaultConfig>;
using StDecision = BasicStDecision<DefaultConfig>;
using StParams = BasicStParams<DefaultConfig>;
using StGraph = BasicStGraph<DefaultConfig>;

}  // namespace itp::speed
