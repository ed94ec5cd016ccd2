#include "sim/scene_generator.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <set>
#include <string>

#include <fmt/format.h>

#include "sim/box_geometry.hpp"

namespace hil::sim {

namespace {

constexpr double kPi = std::numbers::pi;

// Portable uniform draws on top of mt19937_64 (std distributions are
// implementation-defined; these are bit-identical everywhere).
class Rng {
 public:
  Rng(std::uint64_t seed, int index) {
    const auto s = static_cast<std::uint32_t>(seed & 0xffffffffu);
    const auto h = static_cast<std::uint32_t>(seed >> 32);
    const auto i = static_cast<std::uint32_t>(index);
    std::seed_seq seq{s, h, i, 0x17c0ffeeu};
    eng_.seed(seq);
  }
  double uniform() { return static_cast<double>(eng_() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int integer(int lo, int hi) {  // inclusive
    const auto span = static_cast<std::uint64_t>(hi - lo + 1);
    return lo + static_cast<int>(eng_() % span);
  }
  bool chance(double p) { return uniform() < p; }

 private:
  std::mt19937_64 eng_;
};

double smoothstep5(double u) {  // C2 0 -> 1 over u in [0, 1]
  u = std::clamp(u, 0.0, 1.0);
  return u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}

// The reference curve as a curvature profile kappa(s) integrated finely;
// poses at any (s, l), extended straight beyond both ends.
class RefCurve {
 public:
  RefCurve(const std::function<double(double)>& kappa, double length) : length_(length) {
    const auto n = static_cast<std::size_t>(std::ceil(length / kStep)) + 1;
    x_.resize(n);
    y_.resize(n);
    th_.resize(n);
    k_.resize(n);
    x_[0] = y_[0] = th_[0] = 0.0;
    k_[0] = kappa(0.0);
    for (std::size_t i = 1; i < n; ++i) {
      const double s0 = static_cast<double>(i - 1) * kStep;
      const double km = kappa(s0 + 0.5 * kStep);
      const double thm = th_[i - 1] + 0.5 * km * kStep;  // midpoint heading
      x_[i] = x_[i - 1] + kStep * std::cos(thm);
      y_[i] = y_[i - 1] + kStep * std::sin(thm);
      th_[i] = th_[i - 1] + km * kStep;
      k_[i] = kappa(s0 + kStep);
    }
  }
  double length() const { return length_; }
  double kappa(double s) const { return s <= 0.0 || s >= s_max() ? 0.0 : k_[index(s)]; }
  double heading(double s) const {
    if (s <= 0.0) return th_.front();
    if (s >= s_max()) return th_.back();
    const std::size_t i = index(s);
    const double u = (s - static_cast<double>(i) * kStep) / kStep;
    return th_[i] + u * (th_[i + 1] - th_[i]);
  }
  Point2 point(double s, double l) const {
    double x;
    double y;
    const double th = heading(s);
    if (s <= 0.0) {
      x = x_.front() + s * std::cos(th);
      y = y_.front() + s * std::sin(th);
    } else if (s >= s_max()) {
      x = x_.back() + (s - s_max()) * std::cos(th);
      y = y_.back() + (s - s_max()) * std::sin(th);
    } else {
      const std::size_t i = index(s);
      const double u = (s - static_cast<double>(i) * kStep) / kStep;
      x = x_[i] + u * (x_[i + 1] - x_[i]);
      y = y_[i] + u * (y_[i + 1] - y_[i]);
    }
    return {x - l * std::sin(th), y + l * std::cos(th)};
  }

 private:
  static constexpr double kStep = 0.05;  // [m] integration step
  double s_max() const { return static_cast<double>(x_.size() - 1) * kStep; }
  std::size_t index(double s) const {
    return std::min(static_cast<std::size_t>(s / kStep), x_.size() - 2);
  }
  double length_;
  std::vector<double> x_, y_, th_, k_;
};

// Frenet motion state of an obstacle at time t.
struct FrenetState {
  double s = 0.0, l = 0.0;        // [m]
  double ds = 0.0, dl = 0.0;      // [m/s] time derivatives
};

// A dynamic candidate: archetype, box size, motion and appearance time.
struct DynCandidate {
  std::string kind;
  double length = 4.5, width = 1.8;
  double t_appear = 0.0;  // [s] multiple of sample_dt
  double t_settled = 0.0;  // [s] a lane change is over by then
  bool on_map = true;      // false: it would act beyond the end of the road
  std::function<FrenetState(double)> motion;
};

struct Frame {  // everything the placement rules need
  const GeneratorConfig* cfg = nullptr;
  const RefCurve* curve = nullptr;
  int lanes = 2, ego_lane = 0;
  double w = 3.5;
  double v0 = 0.0, v_limit = 0.0;
  double ego_front = 0.0;  // [m] s of the ego's front bumper at t = 0
  double right_b = 0.0, left_b = 0.0;
  Ego ego;
  double lane_centre(int k) const { return (k - ego_lane) * w; }
};

Pose frenet_pose(const RefCurve& c, const FrenetState& f) {
  const Point2 p = c.point(f.s, f.l);
  const double scale = 1.0 - c.kappa(f.s) * f.l;
  const double rel = std::atan2(f.dl, f.ds * scale);
  return Pose{p.x, p.y, wrap_angle(c.heading(f.s) + rel)};
}

double frenet_speed(const RefCurve& c, const FrenetState& f) {
  return std::hypot(f.ds * (1.0 - c.kappa(f.s) * f.l), f.dl);
}

OrientedBox inflate(OrientedBox b, double margin) {
  b.length += 2.0 * margin;
  b.width += 2.0 * margin;
  return b;
}

// The ego driving at constant speed along its lane centre (rule: no obstacle
// may overlap it within the first 2 s).
OrientedBox ego_sweep_box(const Frame& f, double t) {
  const double s = f.v0 * t;
  const Point2 p = f.curve->point(s, 0.0);
  return ego_box(Pose{p.x, p.y, f.curve->heading(s)}, f.ego.length, f.ego.width, f.ego.wheelbase);
}

DynamicObstacle realise(const Frame& f, const DynCandidate& c, int id) {
  DynamicObstacle d;
  d.id = id;
  d.length = c.length;
  d.width = c.width;
  d.kind = c.kind;
  const double dt = f.cfg->sample_dt;
  const int n = static_cast<int>(std::lround(f.cfg->duration / dt));
  const int k0 = static_cast<int>(std::lround(c.t_appear / dt));
  for (int k = k0; k <= n; ++k) {
    const double t = std::round(k * dt * 1e9) / 1e9;  // 1.2, not 1.2000000000000002
    const FrenetState fs = c.motion(t);
    const Pose p = frenet_pose(*f.curve, fs);
    d.trajectory.push_back(TimedPose{t, p.x, p.y, p.heading, frenet_speed(*f.curve, fs)});
  }
  return d;
}

// SL extent of a box given in Frenet terms (small-angle, curvature-safe margin).
struct SlBox {
  double s_min, s_max, l_min, l_max;
};

SlBox sl_extent(double s, double l, double rel_heading, double length, double width) {
  const double c = std::abs(std::cos(rel_heading));
  const double sn = std::abs(std::sin(rel_heading));
  const double hs = 0.5 * (length * c + width * sn) + 0.1;
  const double hl = 0.5 * (length * sn + width * c) + 0.1;
  return {s - hs, s + hs, l - hl, l + hl};
}

bool sweep_clear(const Frame& f, const std::function<std::optional<OrientedBox>(double)>& box_at) {
  for (int k = 0; k <= 20; ++k) {
    const double t = 0.1 * k;
    const auto b = box_at(t);
    if (b && boxes_overlap(inflate(ego_sweep_box(f, t), 0.5), *b)) {
      return false;
    }
  }
  return true;
}

// Does a candidate dynamic obstacle keep clear of the others over the run?
bool dynamic_clear(const Frame& f, const DynamicObstacle& cand,
                   const std::vector<DynamicObstacle>& others) {
  const int n = static_cast<int>(std::lround(f.cfg->duration / f.cfg->sample_dt));
  for (int k = 0; k <= n; ++k) {
    const double t = k * f.cfg->sample_dt;
    const auto pc = pose_at(cand, t);
    if (!pc) continue;
    const OrientedBox bc = inflate(obstacle_box(cand, *pc), 0.3);
    for (const auto& o : others) {
      const auto po = pose_at(o, t);
      if (po && boxes_overlap(bc, obstacle_box(o, *po))) return false;
    }
  }
  return true;
}

// Static vs every dynamic obstacle over the run, at the sample times and halfway between.
bool static_clear_of_dynamics(const Frame& f, const OrientedBox& box,
                              const std::vector<DynamicObstacle>& dyn) {
  const OrientedBox b = inflate(box, 0.3);
  const int n = static_cast<int>(std::lround(2.0 * f.cfg->duration / f.cfg->sample_dt));
  for (const auto& d : dyn) {
    for (int k = 0; k <= n; ++k) {
      const double t = 0.5 * k * f.cfg->sample_dt;
      const auto p = pose_at(d, t);
      if (p && boxes_overlap(b, obstacle_box(d, *p))) return false;
    }
  }
  return true;
}

// Lane-width free passage: statics whose s-ranges come within `gap` of each
// other form a cluster; the drivable width left free beside each cluster must
// contain one interval of at least lane_width.
bool passage_free(const Frame& f, const std::vector<SlBox>& boxes) {
  constexpr double kClusterGap = 8.0;  // [m] too short to weave between obstacles
  for (const SlBox& seed : boxes) {
    // Grow the cluster containing `seed` (transitive s-overlap).
    std::vector<const SlBox*> cluster{&seed};
    double lo = seed.s_min - kClusterGap;
    double hi = seed.s_max + kClusterGap;
    bool grown = true;
    while (grown) {
      grown = false;
      for (const SlBox& b : boxes) {
        if (std::find(cluster.begin(), cluster.end(), &b) != cluster.end()) continue;
        if (b.s_max >= lo && b.s_min <= hi) {
          cluster.push_back(&b);
          lo = std::min(lo, b.s_min - kClusterGap);
          hi = std::max(hi, b.s_max + kClusterGap);
          grown = true;
        }
      }
    }
    std::vector<std::pair<double, double>> occ;
    for (const SlBox* b : cluster) occ.emplace_back(b->l_min, b->l_max);
    std::sort(occ.begin(), occ.end());
    double cursor = f.right_b;
    double best = 0.0;
    for (const auto& [a, b] : occ) {
      best = std::max(best, std::min(a, f.left_b) - cursor);
      cursor = std::max(cursor, b);
    }
    best = std::max(best, f.left_b - cursor);
    if (best < f.w) return false;
  }
  return true;
}

// ---- dynamic archetypes -------------------------------------------------------

DynCandidate make_slow_leader(const Frame& f, Rng& r) {
  DynCandidate c;
  c.kind = std::string(archetype::kSlowLeader);
  c.length = r.uniform(4.2, 5.0);
  c.width = r.uniform(1.7, 1.95);
  const double v = std::max(2.0, f.v0 * r.uniform(0.3, 0.75));
  const double closing = f.v0 - v;
  const double gap = std::max(2.0 * closing + 5.0, closing * closing / (2.0 * f.cfg->max_brake) + 10.0) +
                     r.uniform(5.0, 40.0);
  const double s0 = f.ego_front + gap + 0.5 * c.length;
  const double l = r.uniform(-0.2, 0.2);
  c.motion = [s0, v, l](double t) { return FrenetState{s0 + v * t, l, v, 0.0}; };
  return c;
}

// One of the lanes next to the ego's, drawn uniformly.
int random_adjacent_lane(const Frame& f, Rng& r) {
  std::vector<int> lanes;
  for (int k = 0; k < f.lanes; ++k) {
    if (std::abs(k - f.ego_lane) == 1) lanes.push_back(k);
  }
  return lanes[static_cast<std::size_t>(r.integer(0, static_cast<int>(lanes.size()) - 1))];
}

DynCandidate make_adjacent_car(const Frame& f, Rng& r) {
  DynCandidate c;
  c.kind = std::string(archetype::kAdjacentCar);
  c.length = r.uniform(4.2, 5.0);
  c.width = r.uniform(1.7, 1.95);
  const int lane = random_adjacent_lane(f, r);
  const double v = std::min(1.1 * f.v_limit, std::max(2.0, f.v0 * r.uniform(0.6, 1.3)));
  const double s0 = r.uniform(-25.0, 80.0);
  const double l = f.lane_centre(lane) + r.uniform(-0.2, 0.2);
  c.motion = [s0, v, l](double t) { return FrenetState{s0 + v * t, l, v, 0.0}; };
  return c;
}

// The ego speeding up from v0 to the speed limit at a comfortable 2 m/s²: the
// farthest a careful ego may be by t, for the rules of the cut-ins.
double fastest_ego_speed(const Frame& f, double t) { return std::min(f.v_limit, f.v0 + 2.0 * t); }
double fastest_ego_travel(const Frame& f, double t) {
  const double t_up = std::max(0.0, (f.v_limit - f.v0) / 2.0);
  const double ta = std::min(t, t_up);
  return f.v0 * ta + ta * ta + f.v_limit * std::max(0.0, t - t_up);
}

DynCandidate make_cut_in(const Frame& f, Rng& r) {
  DynCandidate c;
  c.kind = std::string(archetype::kCutIn);
  c.length = r.uniform(4.2, 5.0);
  c.width = r.uniform(1.7, 1.95);
  const int lane = random_adjacent_lane(f, r);
  const double v = std::max(2.0, f.v0 * r.uniform(0.5, 1.0));
  const double t_start = r.uniform(0.5, 3.0);
  const double dur = r.uniform(2.5, 4.0);
  c.t_settled = t_start + dur;
  // Ahead enough that, when it is half-way in, the ego can still stop
  // comfortably behind it, also an ego that sped up to the limit meanwhile.
  const double t_mid = t_start + 0.5 * dur;
  const double closing = fastest_ego_speed(f, t_mid) - v;
  const double need = std::max(0.0, closing * closing / (2.0 * f.cfg->max_brake)) + 8.0;
  const double s0 = f.ego_front + std::max(0.0, fastest_ego_travel(f, t_mid) - v * t_mid) + need +
                    0.5 * c.length + r.uniform(0.0, 30.0);
  const double l_from = f.lane_centre(lane);
  c.motion = [s0, v, l_from, t_start, dur](double t) {
    const double u = (t - t_start) / dur;
    const double sm = smoothstep5(u);
    // d/dt of the quintic smoothstep: 30 u^2 (1-u)^2 / dur
    const double dsm = (u > 0.0 && u < 1.0) ? 30.0 * u * u * (1.0 - u) * (1.0 - u) / dur : 0.0;
    return FrenetState{s0 + v * t, l_from * (1.0 - sm), v, -l_from * dsm};
  };
  return c;
}

DynCandidate make_oncoming(const Frame& f, Rng& r) {
  DynCandidate c;
  c.kind = std::string(archetype::kOncoming);
  c.length = r.uniform(4.2, 5.0);
  c.width = r.uniform(1.7, 1.95);
  const double v = f.v_limit * r.uniform(0.6, 1.0);
  const double s0 = r.uniform(50.0, f.curve->length());
  const double l = f.lane_centre(f.lanes - 1) + r.uniform(-0.2, 0.2);
  c.motion = [s0, v, l](double t) { return FrenetState{s0 - v * t, l, -v, 0.0}; };
  return c;
}

// A vulnerable road user crossing the road at an angle (deviation from
// perpendicular within +-max_dev), stepping on 1 m off the road.
DynCandidate make_crossing(const Frame& f, Rng& r, std::string_view kind, double length, double width,
                           double v_lo, double v_hi, double max_dev, double min_ahead) {
  DynCandidate c;
  c.kind = std::string(kind);
  c.length = length;
  c.width = width;
  const double stop = f.v0 * f.v0 / (2.0 * f.cfg->max_brake) + 10.0;
  const double offset = r.uniform(0.0, 60.0);
  const double v = r.uniform(v_lo, v_hi);
  const double dev = r.uniform(-max_dev, max_dev);
  const bool from_right = r.chance(0.6);
  const double l0 = from_right ? f.right_b - 1.0 : f.left_b + 1.0;
  const double dl = (from_right ? v : -v) * std::cos(dev);
  const double ds = v * std::sin(dev);
  c.t_appear = std::round(r.uniform(0.0, 3.0) / f.cfg->sample_dt) * f.cfg->sample_dt;
  const double t0 = c.t_appear;
  // The distances count from where the ego (at v0) is when it appears: one
  // that steps out closer than a stop is not a planning problem.
  const double s = f.ego_front + f.v0 * t0 + std::max(min_ahead, stop) + offset;
  c.on_map = s <= f.curve->length() - 5.0;
  c.motion = [s, l0, ds, dl, t0](double t) {
    return FrenetState{s + ds * (t - t0), l0 + dl * (t - t0), ds, dl};
  };
  return c;
}

DynCandidate make_pedestrian(const Frame& f, Rng& r) {
  return make_crossing(f, r, archetype::kPedestrian, 1.0, 1.0, 1.0, 1.8, 20.0 * kPi / 180.0, 30.0);
}

DynCandidate make_cyclist(const Frame& f, Rng& r) {
  return make_crossing(f, r, archetype::kCyclist, 1.8, 0.7, 3.0, 5.0, 30.0 * kPi / 180.0, 40.0);
}

// Faster traffic in the next lane coming up from behind and passing the ego.
DynCandidate make_overtaker(const Frame& f, Rng& r) {
  DynCandidate c;
  c.kind = std::string(archetype::kOvertaker);
  c.length = r.uniform(4.2, 5.0);
  c.width = r.uniform(1.7, 1.95);
  const int lane = random_adjacent_lane(f, r);
  const double v = std::min(1.3 * f.v_limit, f.v0 + r.uniform(3.0, 7.0));
  const double s0 = -r.uniform(15.0, 50.0);
  const double l = f.lane_centre(lane) + r.uniform(-0.2, 0.2);
  c.motion = [s0, v, l](double t) { return FrenetState{s0 + v * t, l, v, 0.0}; };
  return c;
}

// A cut-in that then brakes to a stop (2-6 m/s², more where needed to stop
// within the run, at most 7; from 0-2 s after it is in the lane). When the
// braking starts, an ego that sped up to the limit (not following it) would
// still be 3 m beyond RSS's distance (0.5 s, 5 m/s² against its braking).
DynCandidate make_cut_in_brake(const Frame& f, Rng& r) {
  DynCandidate c = make_cut_in(f, r);
  c.kind = std::string(archetype::kCutInBrake);
  const FrenetState start = c.motion(0.0);
  const double v = start.ds;
  const double t_in = c.t_settled + r.uniform(0.0, 2.0);
  // Stopped before the run ends where 7 m/s² at most allows it.
  const double b = std::min(7.0, std::max(r.uniform(2.0, 6.0), v / std::max(0.5, f.cfg->duration - 0.5 - t_in)));
  const double t_stop = v / b;
  const double s_b = c.motion(t_in).s;
  const double v_e = fastest_ego_speed(f, t_in);
  const double need = v_e * 0.5 + std::max(0.0, v_e * v_e / (2.0 * 5.0) - v * v / (2.0 * b)) + 3.0;
  const double gap = s_b - 0.5 * c.length - (f.ego_front + fastest_ego_travel(f, t_in));
  const double shift = std::max(0.0, need - gap);
  const auto lateral = c.motion;
  c.motion = [lateral, shift, t_in, b, t_stop, v](double t) {
    FrenetState fs = lateral(t);
    fs.s += shift;
    if (t > t_in) {
      const double tau = std::min(t - t_in, t_stop);
      fs.s = lateral(t_in).s + shift + v * tau - 0.5 * b * tau * tau;
      fs.ds = std::max(0.0, v - b * (t - t_in));
    }
    return fs;
  };
  return c;
}

struct Weighted {
  std::string_view kind;
  double p;
};
// Fixed archetype probabilities (docs/simulation.md).
constexpr Weighted kDynamicMix[] = {
    {archetype::kSlowLeader, 0.18}, {archetype::kAdjacentCar, 0.14}, {archetype::kCutIn, 0.12},
    {archetype::kCutInBrake, 0.10}, {archetype::kOncoming, 0.12},    {archetype::kPedestrian, 0.12},
    {archetype::kCyclist, 0.08},    {archetype::kOvertaker, 0.14}};
constexpr double kParkedCarProbability = 0.6;  // else debris / cone

std::string_view pick_dynamic(Rng& r) {
  double u = r.uniform();
  for (const auto& w : kDynamicMix) {
    if (u < w.p) return w.kind;
    u -= w.p;
  }
  return kDynamicMix[0].kind;
}

DynCandidate make_dynamic(std::string_view kind, const Frame& f, Rng& r) {
  if (kind == archetype::kAdjacentCar) return make_adjacent_car(f, r);
  if (kind == archetype::kCutIn) return make_cut_in(f, r);
  if (kind == archetype::kOncoming) return make_oncoming(f, r);
  if (kind == archetype::kPedestrian) return make_pedestrian(f, r);
  if (kind == archetype::kCyclist) return make_cyclist(f, r);
  if (kind == archetype::kOvertaker) return make_overtaker(f, r);
  if (kind == archetype::kCutInBrake) return make_cut_in_brake(f, r);
  return make_slow_leader(f, r);
}

// ---- static archetypes ---------------------------------------------------------

struct StaticCandidate {
  std::string kind;
  double s, l, rel_heading, length, width;
};

StaticCandidate make_static(bool parked, const Frame& f, Rng& r) {
  StaticCandidate c;
  const double s_lo = 10.0;
  const double s_hi = f.curve->length() - 10.0;
  if (parked) {
    c.kind = std::string(archetype::kParkedCar);
    c.length = r.uniform(4.2, 4.9);
    c.width = r.uniform(1.7, 1.9);
    c.rel_heading = r.uniform(-0.05, 0.05);
    const double intrusion = r.uniform(0.2, 0.9);  // [m] into the outer lane
    if (r.chance(0.75)) {
      c.l = f.right_b + intrusion - 0.5 * c.width;
    } else {
      c.l = f.left_b - intrusion + 0.5 * c.width;
    }
  } else {
    c.kind = std::string(archetype::kDebris);
    const bool cone = r.chance(0.5);
    c.length = cone ? 0.4 : r.uniform(0.5, 1.5);
    c.width = cone ? 0.4 : r.uniform(0.4, 1.2);
    c.rel_heading = r.uniform(-kPi, kPi);
    const int lane = r.integer(0, f.lanes - 1);
    c.l = f.lane_centre(lane) + r.uniform(-1.2, 1.2);
  }
  c.s = r.uniform(s_lo, s_hi);
  return c;
}

OrientedBox static_box(const Frame& f, const StaticCandidate& c) {
  const Point2 p = f.curve->point(c.s, c.l);
  return OrientedBox{p.x, p.y, wrap_angle(f.curve->heading(c.s) + c.rel_heading), c.length, c.width};
}

}  // namespace

World generate_scene(std::uint64_t seed, int index, const GeneratorConfig& cfg) {
  Rng r(seed, index);
  World w;
  w.name = fmt::format("paper-{:04d}", index);
  w.duration = cfg.duration;

  // Road: lanes, speed limit, geometry.
  Frame f;
  f.cfg = &cfg;
  f.w = cfg.lane_width;
  f.lanes = r.chance(0.5) ? 2 : 3;
  f.ego_lane = (f.lanes == 3 && r.chance(0.5)) ? 1 : 0;  // rightmost or middle
  f.v_limit = std::round(r.uniform(8.0, 20.0) * 10.0) / 10.0;
  f.right_b = -0.5 * f.w - f.ego_lane * f.w;
  f.left_b = (f.lanes - f.ego_lane) * f.w - 0.5 * f.w;

  const double r_min = std::max(50.0, f.v_limit * f.v_limit / cfg.max_lat_acc);
  const double r_max = std::max(3.0 * r_min, 400.0);
  auto draw_kappa = [&]() {
    const double k = r.uniform(1.0 / r_max, 1.0 / r_min);
    return r.chance(0.5) ? k : -k;
  };
  f.v0 = std::round(f.v_limit * r.uniform(0.6, 1.0) * 10.0) / 10.0;
  double length = std::max(r.uniform(150.0, 250.0), f.v_limit * cfg.duration + 100.0);
  // Sometimes the road ends ahead (a dead end, the end of the map): far
  // enough for a comfortable stop (3 m/s²) with 25 m to spare.
  const bool map_end = r.chance(cfg.map_end_probability);
  if (map_end) {
    const double stop = 3.8 + f.v0 * f.v0 / (2.0 * cfg.max_brake) + 25.0;
    length = r.uniform(std::max(80.0, stop), std::max(180.0, stop + 20.0));
  }
  length = std::ceil(length / cfg.ref_spacing) * cfg.ref_spacing;

  const int shape = r.integer(0, 2);  // 0 straight, 1 arc, 2 S-curve
  std::function<double(double)> kappa = [](double) { return 0.0; };
  if (shape == 1) {
    const double s1 = r.uniform(10.0, 60.0);
    const double tr = r.uniform(20.0, 40.0);
    const double hold = r.uniform(40.0, 150.0);
    const double k1 = draw_kappa();
    kappa = [=](double s) {
      return k1 * (smoothstep5((s - s1) / tr) - smoothstep5((s - s1 - tr - hold) / tr));
    };
  } else if (shape == 2) {
    const double s1 = r.uniform(10.0, 40.0);
    const double tr = r.uniform(20.0, 35.0);
    const double hold1 = r.uniform(20.0, 60.0);
    const double hold2 = r.uniform(20.0, 60.0);
    const double k1 = draw_kappa();
    const double k2 = -std::copysign(std::abs(draw_kappa()), k1);
    kappa = [=](double s) {
      const double a = s1;
      const double b = a + tr + hold1;           // start of k1 -> k2 transition
      const double c = b + tr + hold2;           // start of k2 -> 0
      return k1 * smoothstep5((s - a) / tr) + (k2 - k1) * smoothstep5((s - b) / tr) -
             k2 * smoothstep5((s - c) / tr);
    };
  }
  const RefCurve curve(kappa, length);
  f.curve = &curve;
  w.tags.push_back(shape == 0 ? "road:straight" : shape == 1 ? "road:arc" : "road:s-curve");
  w.tags.push_back(fmt::format("lanes:{}", f.lanes));
  w.tags.push_back(f.ego_lane == 0 ? "ego_lane:rightmost" : "ego_lane:middle");
  if (map_end) {
    w.tags.push_back(std::string(archetype::kMapEnd));
  }

  for (double s = 0.0; s <= length + 1e-9; s += cfg.ref_spacing) {
    const Point2 p = curve.point(s, 0.0);
    w.reference_line.push_back(p);
  }
  w.road.lane_width = f.w;
  w.road.left_boundary = Boundary::constant_at(f.left_b);
  w.road.right_boundary = Boundary::constant_at(f.right_b);
  w.road.target_lane_offset = 0.0;
  w.road.speed_limit = f.v_limit;

  // Ego: rear axle at s = 0 on the lane centre.
  f.ego = Ego{0.0, 0.0, curve.heading(0.0), f.v0, 0.0, curve.kappa(0.0), 4.8, 1.9, 2.8};
  f.ego_front = f.ego.wheelbase + 0.5 * (f.ego.length - f.ego.wheelbase);
  w.ego = f.ego;

  // Dynamic obstacles first: static ones are then placed clear of their motion.
  const int n_dyn = r.integer(cfg.min_dynamic, cfg.max_dynamic);
  std::set<std::string> kinds;
  for (int slot = 0; slot < n_dyn; ++slot) {
    std::string_view kind = pick_dynamic(r);
    const int attempts = (static_cast<int>(w.dynamic_obstacles.size()) < cfg.min_dynamic) ? 400 : 60;
    for (int a = 0; a < attempts; ++a) {
      if (a > 0 && a % 20 == 0) kind = pick_dynamic(r);  // this archetype does not fit: another
      const DynCandidate cand = make_dynamic(kind, f, r);
      if (!cand.on_map) continue;
      const DynamicObstacle d =
          realise(f, cand, 11 + static_cast<int>(w.dynamic_obstacles.size()));
      const bool ego_ok = sweep_clear(f, [&](double t) -> std::optional<OrientedBox> {
        const auto p = pose_at(d, t);
        return p ? std::optional<OrientedBox>(obstacle_box(d, *p)) : std::nullopt;
      });
      if (ego_ok && dynamic_clear(f, d, w.dynamic_obstacles)) {
        w.dynamic_obstacles.push_back(d);
        kinds.insert(d.kind);
        break;
      }
    }
  }

  // Static obstacles.
  const int n_static = r.integer(cfg.min_static, cfg.max_static);
  std::vector<SlBox> sl_boxes;
  // Anything reaching into the ego's lane must be beyond the 40 m zone, the
  // 2 s constant-speed reach, and a comfortable stop (v^2 / 2b + 10 m).
  const double s_clear = std::max({40.0, f.ego_front + 2.0 * f.v0 + 5.0,
                                   f.ego_front + f.v0 * f.v0 / (2.0 * cfg.max_brake) + 10.0});
  for (int slot = 0; slot < n_static; ++slot) {
    bool parked = r.chance(kParkedCarProbability);
    const int attempts = (static_cast<int>(w.static_obstacles.size()) < cfg.min_static) ? 400 : 60;
    for (int a = 0; a < attempts; ++a) {
      if (a > 0 && a % 20 == 0) parked = r.chance(kParkedCarProbability);
      const StaticCandidate c = make_static(parked, f, r);
      const SlBox sl = sl_extent(c.s, c.l, c.rel_heading, c.length, c.width);
      const bool in_ego_lane = sl.l_max > -0.5 * f.w && sl.l_min < 0.5 * f.w;
      if (in_ego_lane && sl.s_min < s_clear) continue;
      const OrientedBox box = static_box(f, c);
      bool ok = true;
      for (const auto& o : w.static_obstacles) {
        if (box_distance(box, obstacle_box(o)) < 0.5) {
          ok = false;
          break;
        }
      }
      if (!ok) continue;
      if (!sweep_clear(f, [&](double) { return std::optional<OrientedBox>(box); })) continue;
      if (!static_clear_of_dynamics(f, box, w.dynamic_obstacles)) continue;
      std::vector<SlBox> with = sl_boxes;
      with.push_back(sl);
      if (!passage_free(f, with)) continue;
      sl_boxes = std::move(with);
      w.static_obstacles.push_back(StaticObstacle{static_cast<int>(w.static_obstacles.size()) + 1,
                                                  box.cx, box.cy, box.heading, box.length,
                                                  box.width, c.kind});
      kinds.insert(c.kind);
      break;
    }
  }
  for (const auto& k : kinds) w.tags.push_back(k);
  return w;
}

std::vector<World> default_suite(int count, std::uint64_t seed, const GeneratorConfig& config) {
  std::vector<World> out;
  out.reserve(static_cast<std::size_t>(std::max(0, count)));
  for (int i = 0; i < count; ++i) {
    out.push_back(generate_scene(seed, i, config));
  }
  return out;
}

}  // namespace hil::sim
