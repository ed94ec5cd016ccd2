#include "itp/link/planner_messages.hpp"

#include "itp/configurations.hpp"
#include "itp/link/byte_codec.hpp"

namespace itp::link {
namespace {

constexpr std::uint8_t kResetFlag = 1u;

float f(Scalar v) { return static_cast<float>(v); }
Scalar s(float v) { return static_cast<Scalar>(v); }

// Scene values go through ByteWriter::f32_of: a finite value beyond float
// range fails the encoding instead of reaching the firmware as infinity.
double d(Scalar v) { return static_cast<double>(v); }

template <class Cfg>
void put_boundary(ByteWriter& w, const scene::BasicBoundary<Cfg>& b) {
  w.u8(static_cast<std::uint8_t>(b.table.size()));
  w.f32_of(d(b.offset));
  for (const scene::BoundaryPoint& p : b.table) {  // <= kMaxBoundaryPoints
    w.f32_of(d(p.s));
    w.f32_of(d(p.l));
  }
}

template <class Cfg>
bool get_boundary(ByteReader& r, scene::BasicBoundary<Cfg>& b) {
  const int n = r.u8();
  b.offset = s(r.f32());
  b.table.clear();
  if (n > Cfg::kMaxBoundaryPoints) {
    return false;
  }
  for (int i = 0; i < n; ++i) {  // <= kMaxBoundaryPoints
    scene::BoundaryPoint p;
    p.s = s(r.f32());
    p.l = s(r.f32());
    // Cleared above; n <= kMaxBoundaryPoints = capacity (checked).
    static_cast<void>(b.table.push_back(p));
  }
  return r.ok();
}

}  // namespace

template <class Cfg>
std::size_t encode_scene(const SceneHeader& h, const scene::BasicScene<Cfg>& sc, int stride,
                         std::span<std::uint8_t> out) {
  ByteWriter w(out);
  const double ox = sc.reference_line.empty() ? 0.0 : static_cast<double>(sc.reference_line[0].x);
  const double oy = sc.reference_line.empty() ? 0.0 : static_cast<double>(sc.reference_line[0].y);
  const auto rx = [&](Scalar x) { w.f32_of(static_cast<double>(x) - ox); };
  const auto ry = [&](Scalar y) { w.f32_of(static_cast<double>(y) - oy); };
  w.u32(h.cycle);
  w.f64(h.now);
  w.u8(h.reset ? kResetFlag : 0u);
  w.f64(ox);
  w.f64(oy);
  w.u8(static_cast<std::uint8_t>(sc.reference_line.size()));
  for (const geometry::Point2& p : sc.reference_line) {  // <= kMaxReferencePoints
    rx(p.x);
    ry(p.y);
  }
  w.f32_of(d(sc.road.lane_width));
  w.f32_of(d(sc.road.target_lane_offset));
  w.f32_of(d(sc.road.speed_limit));
  put_boundary(w, sc.road.left);
  put_boundary(w, sc.road.right);
  const scene::Ego& e = sc.ego;
  rx(e.state.x);
  ry(e.state.y);
  for (Scalar v : {e.state.heading, e.state.v, e.state.a, e.state.kappa, e.geometry.length, e.geometry.width,
                   e.geometry.wheelbase, e.limits.a_min, e.limits.a_max, e.limits.lat_acc_max, e.limits.kappa_max}) {
    w.f32_of(d(v));
  }
  w.u8(static_cast<std::uint8_t>(sc.static_obstacles.size()));
  for (const scene::StaticObstacle& o : sc.static_obstacles) {  // <= kMaxStaticObstacles
    w.i32(o.id);
    rx(o.x);
    ry(o.y);
    w.f32_of(d(o.heading));
    w.f32_of(d(o.length));
    w.f32_of(d(o.width));
  }
  w.u8(static_cast<std::uint8_t>(sc.dynamic_obstacles.size()));
  const std::size_t step = stride < 1 ? 1u : static_cast<std::size_t>(stride);
  for (const scene::BasicDynamicObstacle<Cfg>& o :
       sc.dynamic_obstacles) {  // <= kMaxDynamicObstacles
    w.i32(o.id);
    w.f32_of(d(o.length));
    w.f32_of(d(o.width));
    const std::size_t n = o.trajectory.size();
    const std::size_t sent = n == 0 ? 0 : (n - 1) / step + 1 + ((n - 1) % step != 0 ? 1 : 0);
    w.u8(static_cast<std::uint8_t>(sent));
    for (std::size_t i = 0; i < n; ++i) {  // <= kMaxPredictionSamples
      if (i % step != 0 && i + 1 != n) {
        continue;  // thinned; the last sample always goes
      }
      const scene::TimedPose& p = o.trajectory[i];
      w.f32_of(static_cast<double>(p.t) - h.now);
      rx(p.x);
      ry(p.y);
      w.f32_of(d(p.heading));
      w.f32_of(d(p.v));
    }
  }
  return w.ok() ? w.size() : 0;
}

template <class Cfg>
bool decode_scene(std::span<const std::uint8_t> in, SceneHeader& h, scene::BasicScene<Cfg>& sc) {
  ByteReader r(in);
  sc.reset();  // in place: a temporary scene would put ~20 KB on the stack
  h.cycle = r.u32();
  h.now = r.f64();
  h.reset = (r.u8() & kResetFlag) != 0u;
  const double ox = r.f64();
  const double oy = r.f64();
  const auto ax = [&](float x) { return static_cast<Scalar>(ox + static_cast<double>(x)); };
  const auto ay = [&](float y) { return static_cast<Scalar>(oy + static_cast<double>(y)); };
  const int n_ref = r.u8();
  if (n_ref > Cfg::kMaxReferencePoints) {
    return false;
  }
  for (int i = 0; i < n_ref; ++i) {  // <= kMaxReferencePoints
    const float x = r.f32();
    const float y = r.f32();
    // Scene reset above; n_ref <= kMaxReferencePoints = capacity (checked).
    static_cast<void>(sc.reference_line.push_back(geometry::Point2{ax(x), ay(y)}));
  }
  sc.road.lane_width = s(r.f32());
  sc.road.target_lane_offset = s(r.f32());
  sc.road.speed_limit = s(r.f32());
  if (!get_boundary(r, sc.road.left) || !get_boundary(r, sc.road.right)) {
    return false;
  }
  scene::Ego& e = sc.ego;
  e.state.x = ax(r.f32());
  e.state.y = ay(r.f32());
  Scalar* fields[] = {&e.state.heading, &e.state.v, &e.state.a, &e.state.kappa, &e.geometry.length,
                      &e.geometry.width, &e.geometry.wheelbase, &e.limits.a_min, &e.limits.a_max,
                      &e.limits.lat_acc_max, &e.limits.kappa_max};
  for (Scalar* p : fields) {  // 11 fields
    *p = s(r.f32());
  }
  const int n_static = r.u8();
  if (n_static > Cfg::kMaxStaticObstacles) {
    return false;
  }
  for (int i = 0; i < n_static; ++i) {  // <= kMaxStaticObstacles
    scene::StaticObstacle o;
    o.id = r.i32();
    o.x = ax(r.f32());
    o.y = ay(r.f32());
    o.heading = s(r.f32());
    o.length = s(r.f32());
    o.width = s(r.f32());
    // Scene reset above; n_static <= kMaxStaticObstacles = capacity (checked).
    static_cast<void>(sc.static_obstacles.push_back(o));
  }
  const int n_dyn = r.u8();
  if (n_dyn > Cfg::kMaxDynamicObstacles) {
    return false;
  }
  for (int i = 0; i < n_dyn; ++i) {  // <= kMaxDynamicObstacles
    const std::int32_t id = r.i32();
    const Scalar length = s(r.f32());
    const Scalar width = s(r.f32());
    const int n = r.u8();
    if (n > Cfg::kMaxPredictionSamples) {
      return false;
    }
    // Filled in place: a local obstacle (3.2 KB of predictions) copied in
    // would sit on the stack. n_dyn <= capacity, so the slot exists.
    static_cast<void>(sc.dynamic_obstacles.resize(sc.dynamic_obstacles.size() + 1));
    scene::BasicDynamicObstacle<Cfg>& o = sc.dynamic_obstacles.back();
    o.id = id;
    o.length = length;
    o.width = width;
    o.trajectory.clear();
    for (int k = 0; k < n; ++k) {  // <= kMaxPredictionSamples
      scene::TimedPose p;
      p.t = static_cast<Scalar>(h.now + static_cast<double>(r.f32()));
      p.x = ax(r.f32());
      p.y = ay(r.f32());
      p.heading = s(r.f32());
      p.v = s(r.f32());
      // Cleared above; n <= kMaxPredictionSamples = capacity (checked).
      static_cast<void>(o.trajectory.push_back(p));
    }
  }
  return r.done();
}

namespace {

// A reply that plans nothing (the firmware's answer to a scene that does
// not validate): the fields of an empty plan, without its storage.
struct RejectedPlan {
  PlanStatus status = PlanStatus::kInvalidInput;
  planner::FallbackReason fallback = planner::FallbackReason::kNone;
  scene::ValidationReason invalid = scene::ValidationReason::kNone;
  int iterations = 0;
  int qp_solves = 0;
  int qp_iterations = 0;
  planner::StageTiming timing{};
  std::span<const planner::TrajectoryPoint> trajectory{};
  std::span<const planner::ObstacleDecision> decisions{};
};

// One writer for both: P is a BasicPlan or a RejectedPlan.
template <class P>
std::size_t write_plan(const PlanHeader& h, const P& p, std::span<std::uint8_t> out) {
  const double ox = h.origin_x;
  const double oy = h.origin_y;
  ByteWriter w(out);
  w.u32(h.cycle);
  w.u32(h.scene_crc);
  w.u8(static_cast<std::uint8_t>(p.status));
  w.u8(static_cast<std::uint8_t>(p.fallback));
  w.u8(static_cast<std::uint8_t>(p.invalid));
  w.u8(static_cast<std::uint8_t>(p.iterations));
  w.u16(static_cast<std::uint16_t>(p.qp_solves));
  w.u32(static_cast<std::uint32_t>(p.qp_iterations));
  for (std::uint64_t v : {p.timing.prepare, p.timing.decision, p.timing.path, p.timing.speed, p.timing.check,
                          p.timing.total, p.timing.tick_hz}) {
    w.u64(v);
  }
  w.u16(static_cast<std::uint16_t>(p.timing.decision_runs));
  // The cycle's work in the units of its budgets (docs/performance.md, "Worst case").
  w.u64(p.timing.coarse);
  w.u32(static_cast<std::uint32_t>(p.timing.tree_nodes));
  w.u16(static_cast<std::uint16_t>(p.timing.coarse_qps));
  w.u32(static_cast<std::uint32_t>(p.timing.coarse_iterations));
  w.u16(static_cast<std::uint16_t>(p.timing.path_solves));
  w.u32(static_cast<std::uint32_t>(p.timing.path_iterations));
  w.u16(static_cast<std::uint16_t>(p.timing.speed_solves));
  w.u32(static_cast<std::uint32_t>(p.timing.speed_iterations));
  w.f64(ox);
  w.f64(oy);
  w.u8(static_cast<std::uint8_t>(p.trajectory.size()));
  for (const planner::TrajectoryPoint& q : p.trajectory) {  // <= kTrajectorySamples
    w.f32(f(q.t));
    w.f32(static_cast<float>(static_cast<double>(q.x) - ox));
    w.f32(static_cast<float>(static_cast<double>(q.y) - oy));
    for (Scalar v : {q.heading, q.kappa, q.v, q.a, q.s, q.l}) {
      w.f32(f(v));
    }
  }
  w.u8(static_cast<std::uint8_t>(p.decisions.size()));
  for (const planner::ObstacleDecision& d : p.decisions) {  // <= kMaxObstacles
    w.i32(d.obstacle);
    w.u8(static_cast<std::uint8_t>(d.lateral));
    w.u8(static_cast<std::uint8_t>(d.longitudinal));
    w.u8(d.dynamic ? 1u : 0u);
  }
  return w.ok() ? w.size() : 0;
}

}  // namespace

template <class Cfg>
std::size_t encode_plan(const PlanHeader& h, const planner::BasicPlan<Cfg>& p, std::span<std::uint8_t> out) {
  return write_plan(h, p, out);
}

std::size_t encode_rejected_plan(const PlanHeader& h, scene::ValidationReason why, std::span<std::uint8_t> out) {
  RejectedPlan p;
  p.invalid = why;
  return write_plan(h, p, out);
}

template <class Cfg>
bool decode_plan(std::span<const std::uint8_t> in, PlanHeader& h, planner::BasicPlan<Cfg>& p) {
  ByteReader r(in);
  p = planner::BasicPlan<Cfg>{};
  h.cycle = r.u32();
  h.scene_crc = r.u32();
  p.status = static_cast<PlanStatus>(r.u8());
  p.fallback = static_cast<planner::FallbackReason>(r.u8());
  p.invalid = static_cast<scene::ValidationReason>(r.u8());
  p.iterations = r.u8();
  p.qp_solves = r.u16();
  p.qp_iterations = static_cast<int>(r.u32());
  std::uint64_t* timing[] = {&p.timing.prepare, &p.timing.decision, &p.timing.path, &p.timing.speed,
                             &p.timing.check, &p.timing.total, &p.timing.tick_hz};
  for (std::uint64_t* t : timing) {  // 7 fields
    *t = r.u64();
  }
  p.timing.decision_runs = r.u16();
  p.timing.coarse = r.u64();
  p.timing.tree_nodes = static_cast<int>(r.u32());
  p.timing.coarse_qps = r.u16();
  p.timing.coarse_iterations = static_cast<int>(r.u32());
  p.timing.path_solves = r.u16();
  p.timing.path_iterations = static_cast<int>(r.u32());
  p.timing.speed_solves = r.u16();
  p.timing.speed_iterations = static_cast<int>(r.u32());
  h.origin_x = r.f64();
  h.origin_y = r.f64();
  const double ox = h.origin_x;
  const double oy = h.origin_y;
  const int n = r.u8();
  if (n > Cfg::kTrajectorySamples) {
    return false;
  }
  for (int i = 0; i < n; ++i) {  // <= kTrajectorySamples
    planner::TrajectoryPoint q;
    q.t = s(r.f32());
    q.x = static_cast<Scalar>(ox + static_cast<double>(r.f32()));
    q.y = static_cast<Scalar>(oy + static_cast<double>(r.f32()));
    Scalar* fields[] = {&q.heading, &q.kappa, &q.v, &q.a, &q.s, &q.l};
    for (Scalar* v : fields) {  // 6 fields
      *v = s(r.f32());
    }
    // Plan reset above; n <= kTrajectorySamples = capacity (checked).
    static_cast<void>(p.trajectory.push_back(q));
  }
  const int nd = r.u8();
  if (nd > Cfg::kMaxObstacles) {
    return false;
  }
  for (int i = 0; i < nd; ++i) {  // <= kMaxObstacles
    planner::ObstacleDecision d;
    d.obstacle = r.i32();
    d.lateral = static_cast<planner::LateralSide>(r.u8());
    d.longitudinal = static_cast<speed::Longitudinal>(r.u8());
    d.dynamic = r.u8() != 0u;
    // Plan reset above; nd <= kMaxObstacles = capacity (checked).
    static_cast<void>(p.decisions.push_back(d));
  }
  return r.done();
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                                                                         \
  static_assert(fits_link<C>(), "a scene or plan of this configuration does not fit the link"); \
  template std::size_t encode_scene<C>(const SceneHeader&, const scene::BasicScene<C>&, int,       \
                                       std::span<std::uint8_t>);                                   \
  template bool decode_scene<C>(std::span<const std::uint8_t>, SceneHeader&,                       \
                                scene::BasicScene<C>&);                                            \
  template std::size_t encode_plan<C>(const PlanHeader&, const planner::BasicPlan<C>&,             \
                                      std::span<std::uint8_t>);                                    \
  template bool decode_plan<C>(std::span<const std::uint8_t>, PlanHeader&, planner::BasicPlan<C>&);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::link
