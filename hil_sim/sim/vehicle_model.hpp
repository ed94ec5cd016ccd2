#pragma once
// Kinematic bicycle about the rear axle and a trajectory-tracking controller.
#include <span>
#include <vector>

#include "sim/world.hpp"

namespace hil::sim {

struct VehicleParams {
  double wheelbase = 2.8;        // [m]
  double length = 4.8;           // [m]
  double width = 1.9;            // [m]
  double max_steer = 0.6;        // [rad] |delta| limit
  double max_steer_rate = 0.8;   // [rad/s] actuator slew limit (<= 0: unlimited)
  double max_accel = 3.0;        // [m/s^2]
  double max_decel = 8.0;        // [m/s^2] (positive number; a >= -max_decel)
  double substep = 0.01;         // [s] integration step
};

struct VehicleState {
  double x = 0.0;        // [m] rear-axle centre
  double y = 0.0;        // [m]
  double heading = 0.0;  // [rad]
  double v = 0.0;        // [m/s] >= 0 (no reversing)
  double a = 0.0;        // [m/s^2] acceleration applied over the last substep
  double steer = 0.0;    // [rad] front wheel angle
  double kappa(double wheelbase) const;  // [1/m] tan(steer) / wheelbase
};

struct VehicleCommand {
  double accel = 0.0;  // [m/s^2] requested longitudinal acceleration
  double steer = 0.0;  // [rad] requested front wheel angle
};

// Integrates dx = v cos th, dy = v sin th, dth = v tan(delta) / L, dv = a over
// `dt` in substeps; each substep is integrated exactly for constant steer and
// accel (arc of length v h + a h^2 / 2), so a constant command draws an exact
// circle. Speed stops at 0. Command limits and steer rate are applied here.
void step_vehicle(VehicleState& state, const VehicleParams& params, const VehicleCommand& cmd,
                  double dt);

VehicleState vehicle_from_ego(const Ego& ego, const VehicleParams& params);

// One sample of a planned trajectory (plan/1's fields, x, y = rear axle).
struct TrajectoryPoint {
  double t = 0.0;        // [s] relative to the plan's start
  double x = 0.0;        // [m]
  double y = 0.0;        // [m]
  double heading = 0.0;  // [rad]
  double kappa = 0.0;    // [1/m]
  double v = 0.0;        // [m/s]
  double a = 0.0;        // [m/s^2]
};

// Linear interpolation in t (shortest-arc heading), clamped to the plan's ends.
TrajectoryPoint sample_plan(std::span<const TrajectoryPoint> plan, double t);

struct TrackingGains {
  double lookahead_min = 4.0;     // [m] L_d = max(min, time * v): error decay length
  double lookahead_time = 0.8;    // [s]
  double speed_p = 1.0;           // [1/s] on v_ref - v
};

struct TrackingErrors {
  double lateral = 0.0;   // [m] ego left of the plan's path: positive
  double heading = 0.0;   // [rad] ego heading - path heading
  double speed = 0.0;     // [m/s] v_ref - v
};

// Follows a planned trajectory. Steering: curvature feed-forward from the
// nearest path point plus a linearised Stanley law on lateral and heading
// error, kappa_cmd = kappa_ref - e / L_d^2 - 2 psi / L_d (critically damped
// in distance travelled); delta = atan(L kappa_cmd). Speed: a = a_ref(t) +
// k_v (v_ref(t) - v). Emergency brake: decelerate at a fixed rate, hold steer.
class TrackingController {
 public:
  explicit TrackingController(VehicleParams params = {}, TrackingGains gains = {});

  // A new plan, its t = 0 at absolute time t_start [s].
  void set_plan(std::vector<TrajectoryPoint> plan, double t_start);
  void emergency_brake(double decel);  // [m/s^2] positive; until the next set_plan()
  // No fresh plan: keep following the last one along its path, its speed
  // capped so that braking at `decel` [m/s^2] stops the vehicle by the
  // plan's last sample (it never runs past what was planned). Until the next
  // set_plan(); ignored while an emergency brake is on.
  void stop_within_plan(double decel);
  bool braking() const { return braking_; }
  bool stopping_within_plan() const { return within_plan_; }
  bool has_plan() const { return !plan_.empty(); }

  VehicleCommand command(const VehicleState& s, double t_now);
  const TrackingErrors& last_errors() const { return errors_; }

  // Convenience: runs command + step_vehicle every substep for dt seconds.
  void advance(VehicleState& s, double t_now, double dt);

 private:
  VehicleParams params_;
  TrackingGains gains_;
  std::vector<TrajectoryPoint> plan_;
  double t_start_ = 0.0;
  bool braking_ = false;
  double brake_decel_ = 0.0;
  bool within_plan_ = false;
  double within_plan_decel_ = 0.0;
  TrackingErrors errors_;
};

}  // namespace hil::sim
