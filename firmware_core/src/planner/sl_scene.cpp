#include "itp/planner/sl_scene.hpp"

#include <cmath>
#include <span>

#include "itp/configurations.hpp"
#include "itp/core/scalar_math.hpp"
#include "itp/geometry/angle.hpp"
#include "itp/geometry/frenet.hpp"
#include "itp/planner/road_prediction.hpp"

namespace itp::planner {
namespace {

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
// A car alongside in another lane at least this close to the ego's speed
// (or faster) is treated as coming from behind: its lane ahead is its own.
constexpr Scalar kAlongsideSpeedSlack = Scalar(1);                   // [m/s]

// A road edge moved inwards by `shift` (> 0: towards the left).
template <class Cfg>
decision::BasicLateralProfile<Cfg> to_profile(const scene::BasicBoundary<Cfg>& b, Scalar shift) {
  if (b.is_constant()) {
    return decision::BasicLateralProfile<Cfg>::constant(b.offset + shift);
  }
  decision::BasicLateralProfile<Cfg> p;
  for (const scene::BoundaryPoint& q : b.table) {  // <= kMaxBoundaryPoints
    static_cast<void>(p.add(q.s, q.l + shift));  // same capacity, s validated ascending
  }
  return p;
}

// SL box of a moving obstacle from one projection of its centre: the box's
// half extents along and across the reference at its relative heading. Its
// error on a curved road is about κ·L²/8 (6 cm for a 5 m car on a 50 m
// radius), well inside the dynamic margin; 355 boxes per cycle make the exact
// edge-sampled version (sl_bounding_box, about 20 projections each) the
// planner's largest cost.
template <class Cfg>
geometry::SlBox moving_box_sl(const geometry::BasicReferenceLine<Cfg>& line, Scalar x, Scalar y,
                              Scalar heading, Scalar length, Scalar width, Scalar margin,
                              std::int32_t id) {
  geometry::CurveSample foot;
  const geometry::FrenetPoint c = line.to_frenet(geometry::Point2{x, y}, foot);
  const Scalar rel = geometry::relative_heading(heading, foot.heading);
  const Scalar cs = std::fabs(std::cos(rel));
  const Scalar sn = std::fabs(std::sin(rel));
  const Scalar half_s = Scalar(0.5) * (cs * length + sn * width) + margin;
  const Scalar half_l = Scalar(0.5) * (sn * length + cs * width) + margin;
  return geometry::SlBox{c.s - half_s, c.s + half_s, c.l - half_l, c.l + half_l, id, true};
}

// Marks in `keep` the `n` entries of `key` with the smallest keys (ties: the
// earlier one), all of them when there are at most n. O(size^2); the spans
// are at most a scene's obstacles. (Spans, not arrays per capacity: GCC folds
// the configurations' identical instances and then warns about their bounds.)
void keep_most_relevant(std::span<const Scalar> key, std::size_t n, std::span<bool> keep) {
  for (std::size_t i = 0; i < key.size() && i < keep.size(); ++i) {  // <= kMaxStatic/DynamicObstacles
    std::size_t better = 0;  // entries that rank before entry i
    for (std::size_t j = 0; j < key.size(); ++j) {  // <= kMaxStatic/DynamicObstacles
      better += (key[j] < key[i] || (key[j] == key[i] && j < i)) ? 1u : 0u;
    }
    keep[i] = better < n;
  }
}

}  // namespace

template <class Cfg>
void BasicSlScene<Cfg>::build(const Scene& scene, const ReferenceLine& line, Scalar now,
                              Scalar s_start, Scalar s_end, const PlannerSettings& settings) {
  rear_ = scene::rear_overhang(scene.ego.geometry);
  front_ = scene.ego.geometry.length - rear_;
  s_start_ = s_start;
  ego_l_ = line.to_frenet(geometry::Point2{scene.ego.state.x, scene.ego.state.y}).l;
  ego_v_ = scene.ego.state.v;
  road_margin_ = settings.road_margin;
  dynamic_margin_ = settings.dynamic_margin;
  road_.left = to_profile(scene.road.left, -settings.road_margin);
  road_.right = to_profile(scene.road.right, settings.road_margin);
  road_.lane_width = scene.road.lane_width;
  road_.target_lane_offset = scene.road.target_lane_offset;
  decision::select_road_cuts(road_, s_start, s_end, settings.road_cut_tolerance, settings.road_cut_min_slice);
  project_statics(scene, line, s_end, settings.static_margin);
  project_dynamics(scene, line, now, settings.dynamic_margin);
}

// The decision stage holds Cfg::kDecisionStatics static boxes. A scene with
// more gives it the relevant ones: a box inside the SL window the path can
// use (from the ego's rear to the end of the horizon) and overlapping the
// road between its edges ranks by its distance ahead of the ego (0 when the
// ego is beside it), nearest first; the others rank last. Ties keep the
// scene's order, and so does the selection.
template <class Cfg>
void BasicSlScene<Cfg>::project_statics(const Scene& scene, const ReferenceLine& line, Scalar s_end,
                                        Scalar static_margin) {
  constexpr std::size_t kScene = static_cast<std::size_t>(Cfg::kMaxStaticObstacles);
  constexpr Scalar kIrrelevant = Scalar(1e30);
  std::array<geometry::SlBox, kScene> all{};
  std::array<Scalar, kScene> key{};
  const std::size_t count = scene.static_obstacles.size();
  for (std::size_t i = 0; i < count; ++i) {  // <= kMaxStaticObstacles
    const scene::StaticObstacle& o = scene.static_obstacles[i];
    const geometry::SlBox b = geometry::sl_bounding_box(
        line, geometry::OrientedBox{{o.x, o.y}, o.heading, o.length, o.width}, static_margin);
    // Inflated in s by the ego's extents, so constraints on the rear axle cover the car.
    all[i] = geometry::SlBox{b.s_min - front_, b.s_max + rear_, b.l_min, b.l_max, o.id, false};
    const Scalar s_mid = Scalar(0.5) * (all[i].s_min + all[i].s_max);
    const bool in_window = all[i].s_max >= s_start_ && all[i].s_min <= s_end;
    const bool on_road = all[i].l_min < road_.left.at(s_mid) && all[i].l_max > road_.right.at(s_mid);
    key[i] = in_window && on_road ? max_of(all[i].s_min - s_start_, Scalar(0)) : kIrrelevant;
  }
  std::array<bool, kScene> keep{};
  keep_most_relevant(std::span<const Scalar>(key).first(count), static_cast<std::size_t>(Cfg::kDecisionStatics), keep);
  boxes_.clear();
  statics_left_out_ = 0;
  for (std::size_t i = 0; i < count; ++i) {  // <= kMaxStaticObstacles
    if (keep[i]) {
      // Cleared above; kept <= kDecisionStatics < kMaxDecisionObstacles = capacity.
      static_cast<void>(boxes_.push_back(all[i]));
    } else {
      ++statics_left_out_;
    }
  }
  static_count_ = boxes_.size();
}

template <class Cfg>
void BasicSlScene<Cfg>::project_dynamics(const Scene& scene, const ReferenceLine& line, Scalar now,
                                         Scalar dynamic_margin) {
  constexpr int kSamples = Cfg::kStSamples;
  track_count_ = 0;
  for (const scene::BasicDynamicObstacle<Cfg>& o : scene.dynamic_obstacles) {  // <= kMaxDynamicObstacles
    DynamicTrack& tr = tracks_[static_cast<std::size_t>(track_count_)];
    Motion& motion = motion_[static_cast<std::size_t>(track_count_)];
    ++track_count_;
    tr.id = o.id;
    tr.sweep_occupied = false;
    tr.from_behind = false;
    tr.follower = false;
    tr.crossing = false;
    bool seen = false;
    bool on_road = false;  // first seen on the road: its prediction stays there
    static_cast<void>(predict_along_road(line, road_, o, now, kDt, motion));
    for (int k = 0; k < kSamples; ++k) {  // Cfg::kStSamples
      const auto u = static_cast<std::size_t>(k);
      const scene::ObstacleSample& p = motion[u];
      tr.present[u] = p.present;
      if (!p.present) {
        continue;
      }
      tr.box[u] = moving_box_sl(line, p.x, p.y, p.heading, o.length, o.width, dynamic_margin, o.id);
      const Scalar s_mid = Scalar(0.5) * (tr.box[u].s_min + tr.box[u].s_max);
      // Classified where first seen on the reference line (behind its start
      // the frame runs straight on, so lanes mean nothing there).
      if (!seen && (s_mid >= 0 || k == kSamples - 1)) {
        seen = true;
        const Scalar rel = geometry::relative_heading(p.heading, line.evaluate(s_mid).heading);
        const bool oncoming = std::fabs(rel) > kOncomingHeading;
        const Scalar l_mid = Scalar(0.5) * (tr.box[u].l_min + tr.box[u].l_max);
        // Approaching from behind, or alongside and not slower, in another
        // lane than the ego's target lane: the ego must not move in (or stay)
        // ahead of it (it would be in its way). A follower in the target lane
        // is its own business.
        const bool behind = tr.box[u].s_max < s_start_;
        const bool alongside = tr.box[u].s_min < s_start_ + front_ &&
                               p.v * std::cos(rel) >= ego_v_ - kAlongsideSpeedSlack;
        const bool other_lane = std::fabs(l_mid - lane_target()) > Scalar(0.5) * road_.lane_width;
        const bool from_behind = (behind || alongside) && other_lane;
        tr.crossing = std::fabs(rel) > kCrossingHeadingLow && std::fabs(rel) < kCrossingHeadingHigh &&
                      std::fabs(p.v) >= kCrossingMinSpeed;
        tr.sweep_occupied = !tr.crossing && (oncoming || from_behind);
        tr.from_behind = tr.sweep_occupied && !oncoming;
        // First seen behind the ego in its (target) lane, coming its way, with
        // the ego in that lane: a follower (the ST graph's; never a wall).
        // Behind where the ego is by then at its speed: it may be first seen
        // on the reference line a few samples on.
        const bool ego_in_lane = std::fabs(ego_l_ - lane_target()) < Scalar(0.5) * road_.lane_width;
        const bool behind_then =
            tr.box[u].s_max < s_start_ + max_of(ego_v_, Scalar(0)) * kDt * static_cast<Scalar>(k);
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
// road edges (when they fit), where the road bends the real obstacle. The
// obstacle's body (the box less the dynamic margin) stays inside the real
// edges: the edges moved in by the road margin (the ego's tracking room) and
// the margin-inflated box pushed a car in the outer lane of a narrow road
// 0.2 m (0.15 + 0.5 - its room) towards the ego.
template <class Cfg>
void BasicSlScene<Cfg>::keep_on_road(Scalar s, geometry::SlBox& box) const {
  const Scalar lo = road_.right.at(s) - road_margin_;
  const Scalar hi = road_.left.at(s) + road_margin_;
  const Scalar body_lo = box.l_min + dynamic_margin_;
  const Scalar body_hi = box.l_max - dynamic_margin_;
  if (body_hi - body_lo > hi - lo) {
    return;
  }
  const Scalar shift = body_hi > hi ? hi - body_hi : (body_lo < lo ? lo - body_lo : Scalar(0));
  box.l_min += shift;
  box.l_max += shift;
}

// An oncoming obstacle sweeps its way towards and past the ego: the ego
// cannot pass it on the side it comes from, nor use its lane in between (a
// manoeuvre there that stalls leaves the ego in its way). The same holds for
// traffic coming up from behind in another lane: cutting in ahead of it and
// slowing down gets the ego hit. Its box is everything it covers over the
// horizon from the ego on (behind the ego nothing is planned, and behind the
// reference line's start the frame runs straight, not along the lanes).
template <class Cfg>
bool BasicSlScene<Cfg>::occupied_sweep(const DynamicTrack& tr, geometry::SlBox& b) const {
  // Traffic from behind that moves over into the ego's target lane becomes a
  // follower there (its own business, RSS): its sweep covers only the
  // lane(s) it comes from, never the target lane.
  const Scalar half_lane = Scalar(0.5) * road_.lane_width;
  bool any = false;
  for (std::size_t u = 0; u < static_cast<std::size_t>(Cfg::kStSamples); ++u) {  // Cfg::kStSamples
    const Scalar s_mid = Scalar(0.5) * (tr.box[u].s_min + tr.box[u].s_max);
    if (!tr.present[u] || tr.box[u].s_max < s_start_ - rear_ || s_mid < 0) {
      continue;
    }
    geometry::SlBox q = tr.box[u];
    if (tr.from_behind) {
      const Scalar l_mid = Scalar(0.5) * (q.l_min + q.l_max);
      if (std::fabs(l_mid - lane_target()) < half_lane) {
        continue;  // in the target lane: a follower there
      }
      if (l_mid > lane_target()) {
        q.l_min = max_of(q.l_min, lane_target() + half_lane);
      } else {
        q.l_max = min_of(q.l_max, lane_target() - half_lane);
      }
      if (!any) {
        b = q;  // not the meeting box: that may lie in the target lane
      }
    }
    any = true;
    b.s_min = min_of(b.s_min, q.s_min);
    b.s_max = max_of(b.s_max, q.s_max);
    b.l_min = min_of(b.l_min, q.l_min);
    b.l_max = max_of(b.l_max, q.l_max);
  }
  return any || !tr.from_behind;
}

// Dynamic obstacles enter the convex space where the ego meets them: the first
// sample at which the ego's guessed position lies within the obstacle's
// s-extent (grown by the ego's length); obstacles the ego never reaches sit at
// their last predicted place.
template <class Cfg>
int BasicSlScene<Cfg>::place_dynamic(const StSamples& s_guess, const bool* skip) {
  constexpr int kSamples = Cfg::kStSamples;
  constexpr std::size_t kScene = static_cast<std::size_t>(Cfg::kMaxDynamicObstacles);
  while (boxes_.size() > static_count_) {  // <= kMaxDynamicObstacles: last round's dynamic boxes
    boxes_.pop_back();
  }
  std::array<geometry::SlBox, kScene> placed_box{};
  std::array<Scalar, kScene> key{};
  std::size_t count = 0;
  for (int i = 0; i < track_count_; ++i) {  // <= kMaxDynamicObstacles
    const DynamicTrack& tr = tracks_[static_cast<std::size_t>(i)];
    if (skip[i] || tr.crossing || tr.follower) {
      continue;  // the ST graph's alone
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
    geometry::SlBox b = tr.box[static_cast<std::size_t>(k)];
    if (tr.sweep_occupied && !occupied_sweep(tr, b)) {
      continue;  // all of it ahead of the ego lies in the target lane
    }
    b.s_min -= front_;
    b.s_max += rear_;
    placed_box[count] = b;
    key[count] = max_of(b.s_min - s_start_, Scalar(0));  // nearest ahead first
    ++count;
  }
  std::array<bool, kScene> keep{};
  keep_most_relevant(std::span<const Scalar>(key).first(count), boxes_.capacity() - boxes_.size(), keep);
  int placed = 0;
  for (std::size_t i = 0; i < count; ++i) {  // <= kMaxDynamicObstacles
    if (keep[i] && boxes_.push_back(placed_box[i])) {
      ++placed;
    }
  }
  return placed;
}

template <class Cfg>
int BasicSlScene<Cfg>::nearest_dynamic(const bool* skip, Scalar s_lo, Scalar s_hi) const {
  int found = -1;
  Scalar nearest = Scalar(0);
  for (std::size_t i = static_count_; i < boxes_.size(); ++i) {  // <= kMaxDynamicObstacles
    const geometry::SlBox& b = boxes_[i];
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

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C) template class BasicSlScene<C>;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::planner
