#include "sim/vehicle_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/box_geometry.hpp"

namespace hil::sim {

double VehicleState::kappa(double wheelbase) const { return std::tan(steer) / wheelbase; }

VehicleState vehicle_from_ego(const Ego& e, const VehicleParams& p) {
  VehicleState s;
  s.x = e.x;
  s.y = e.y;
  s.heading = e.heading;
  s.v = std::max(0.0, e.v);
  s.a = e.a;
  s.steer = std::clamp(std::atan(e.kappa * p.wheelbase), -p.max_steer, p.max_steer);
  return s;
}

void step_vehicle(VehicleState& st, const VehicleParams& p, const VehicleCommand& cmd, double dt) {
  const int n = std::max(1, static_cast<int>(std::lround(dt / p.substep)));
  const double h = dt / n;
  const double target_steer = std::clamp(cmd.steer, -p.max_steer, p.max_steer);
  const double accel = std::clamp(cmd.accel, -p.max_decel, p.max_accel);
  for (int i = 0; i < n; ++i) {
    if (p.max_steer_rate > 0.0) {
      const double d = p.max_steer_rate * h;
      st.steer += std::clamp(target_steer - st.steer, -d, d);
    } else {
      st.steer = target_steer;
    }
    // Distance over the substep; the car stops at v = 0 and does not reverse.
    double ds;
    double a = accel;
    if (st.v + a * h < 0.0) {
      ds = (a < 0.0) ? st.v * st.v / (-2.0 * a) : 0.0;
      a = (h > 0.0) ? -st.v / h : 0.0;
      st.v = 0.0;
    } else {
      ds = st.v * h + 0.5 * a * h * h;
      st.v += a * h;
    }
    st.a = a;
    const double k = std::tan(st.steer) / p.wheelbase;
    const double dth = k * ds;
    if (std::abs(dth) < 1e-9) {
      const double hm = st.heading + 0.5 * dth;
      st.x += ds * std::cos(hm);
      st.y += ds * std::sin(hm);
    } else {
      st.x += (std::sin(st.heading + dth) - std::sin(st.heading)) / k;
      st.y += (std::cos(st.heading) - std::cos(st.heading + dth)) / k;
    }
    st.heading = wrap_angle(st.heading + dth);
  }
}

TrajectoryPoint sample_plan(std::span<const TrajectoryPoint> plan, double t) {
  if (plan.empty()) return {};
  if (t <= plan.front().t) return plan.front();
  if (t >= plan.back().t) return plan.back();
  const auto it = std::upper_bound(plan.begin(), plan.end(), t,
                                   [](double tv, const TrajectoryPoint& q) { return tv < q.t; });
  const TrajectoryPoint& b = *it;
  const TrajectoryPoint& a = *(it - 1);
  const double u = (t - a.t) / (b.t - a.t);
  auto lerp = [u](double p, double q) { return p + u * (q - p); };
  return TrajectoryPoint{t,
                         lerp(a.x, b.x),
                         lerp(a.y, b.y),
                         wrap_angle(a.heading + u * wrap_angle(b.heading - a.heading)),
                         lerp(a.kappa, b.kappa),
                         lerp(a.v, b.v),
                         lerp(a.a, b.a)};
}

TrackingController::TrackingController(VehicleParams params, TrackingGains gains)
    : params_(params), gains_(gains) {}

void TrackingController::set_plan(std::vector<TrajectoryPoint> plan, double t_start) {
  plan_ = std::move(plan);
  t_start_ = t_start;
  braking_ = false;
  within_plan_ = false;
}

void TrackingController::stop_within_plan(double decel) {
  if (braking_ || plan_.empty()) {
    return;
  }
  within_plan_ = true;
  within_plan_decel_ = std::abs(decel);
}

void TrackingController::emergency_brake(double decel) {
  braking_ = true;
  brake_decel_ = std::abs(decel);
}

VehicleCommand TrackingController::command(const VehicleState& s, double t_now) {
  if (braking_ || plan_.empty()) {
    errors_ = {};
    return VehicleCommand{braking_ ? -brake_decel_ : -params_.max_decel, s.steer};
  }
  // Nearest point of the plan's path (segments between samples), with its
  // curvature and heading interpolated along the segment.
  double best = std::numeric_limits<double>::infinity();
  TrajectoryPoint ref = plan_.front();
  double lateral = 0.0;
  if (plan_.size() == 1) {
    const double c = std::cos(ref.heading);
    const double sn = std::sin(ref.heading);
    lateral = -(s.x - ref.x) * sn + (s.y - ref.y) * c;
  }
  for (std::size_t i = 0; i + 1 < plan_.size(); ++i) {
    const TrajectoryPoint& a = plan_[i];
    const TrajectoryPoint& b = plan_[i + 1];
    const double dx = b.x - a.x;
    const double dy = b.y - a.y;
    const double len2 = dx * dx + dy * dy;
    double u = len2 > 1e-12 ? ((s.x - a.x) * dx + (s.y - a.y) * dy) / len2 : 0.0;
    const double lo = (i == 0) ? -1e9 : 0.0;  // extend the first/last segments
    const double hi = (i + 2 == plan_.size()) ? 1e9 : 1.0;
    u = std::clamp(u, lo, hi);
    const double fx = a.x + u * dx;
    const double fy = a.y + u * dy;
    const double d2 = (s.x - fx) * (s.x - fx) + (s.y - fy) * (s.y - fy);
    if (d2 < best) {
      best = d2;
      const double uc = std::clamp(u, 0.0, 1.0);
      ref.heading = len2 > 1e-12 ? std::atan2(dy, dx)
                                 : wrap_angle(a.heading + uc * wrap_angle(b.heading - a.heading));
      ref.kappa = a.kappa + uc * (b.kappa - a.kappa);
      const double len = std::sqrt(len2);
      lateral = len > 1e-6 ? (dx * (s.y - a.y) - dy * (s.x - a.x)) / len : 0.0;
      // Chord -> arc: a path of curvature k bulges k c^2 u (1-u) / 2 to its right.
      lateral += 0.5 * ref.kappa * len2 * uc * (1.0 - uc);
      ref.heading = wrap_angle(ref.heading + ref.kappa * len * (uc - 0.5));
    }
  }
  const double psi = wrap_angle(s.heading - ref.heading);
  const double ld = std::max(gains_.lookahead_min, gains_.lookahead_time * s.v);
  const double k_cmd = ref.kappa - lateral / (ld * ld) - 2.0 * std::sin(psi) / ld;
  TrajectoryPoint tp = sample_plan(plan_, t_now - t_start_);
  if (within_plan_) {
    // v <= decel * (time left on the plan): standing still at its last sample.
    const double left = std::max(0.0, plan_.back().t - (t_now - t_start_));
    const double v_cap = within_plan_decel_ * left;
    if (tp.v > v_cap) {
      tp.v = v_cap;
      tp.a = -within_plan_decel_;
    }
  }
  errors_ = TrackingErrors{lateral, psi, tp.v - s.v};
  double accel = tp.a + gains_.speed_p * (tp.v - s.v);
  if (tp.v <= 0.0 && s.v < 0.05) accel = std::min(accel, 0.0);  // stay stopped
  return VehicleCommand{accel, std::atan(params_.wheelbase * k_cmd)};
}

void TrackingController::advance(VehicleState& s, double t_now, double dt) {
  const int n = std::max(1, static_cast<int>(std::lround(dt / params_.substep)));
  const double h = dt / n;
  for (int i = 0; i < n; ++i) {
    step_vehicle(s, params_, command(s, t_now + i * h), h);
  }
}

}  // namespace hil::sim
