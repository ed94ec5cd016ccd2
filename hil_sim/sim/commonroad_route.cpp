#include "sim/commonroad_route.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include "sim/box_geometry.hpp"

namespace hil::sim {
namespace {

namespace cr = formats::commonroad;

constexpr double kEgoOutsideTolerance = 0.5;  // [m] the ego may lie this far outside its lanelet
constexpr double kEdgeSampleSpacing = 0.5;    // [m] outer bounds sampled at least this densely
constexpr double kEdgeKnotSpacing = 1.0;      // [m] knots of the [s, l] edges
constexpr double kMinPointSpacing = 0.5;      // [m] reference-line points closer are merged
constexpr double kMaxTurnPerPoint = std::numbers::pi / 4;  // [rad] sharper kinks are dropped
constexpr int kMaxLanesAcross = 16;           // neighbours walked on each side, at most
constexpr int kMaxGoalSearch = 200;           // lanelets searched for a goal from a branch
// Points inserted into one polyline segment, at most: 10 km at 0.5 m. A longer
// segment (no road has one; the reader refuses a bound longer than
// limits::kMaxBoundLength, but build_route may be given any Scenario) is
// sampled more coarsely instead of overflowing the count (found by
// fuzz_commonroad before the limits: 1e10 m).
constexpr double kMaxDensifiedSteps = 20000;

Point2 to_point(const cr::Vec2& v) { return {v.x, v.y}; }

std::vector<Point2> to_points(const std::vector<cr::Vec2>& v) {
  std::vector<Point2> out;
  out.reserve(v.size());
  for (const cr::Vec2& p : v) out.push_back(to_point(p));
  return out;
}

double heading_of(Point2 a, Point2 b) { return std::atan2(b.y - a.y, b.x - a.x); }

// The point at fraction u in [0, 1] of the polyline's length.
Point2 at_fraction(const std::vector<Point2>& line, const std::vector<double>& arc, double u) {
  const Pose p = polyline_pose(line, arc, u * arc.back());
  return {p.x, p.y};
}

// Vertices plus points inserted so that no gap exceeds `spacing`.
std::vector<Point2> densified(const std::vector<Point2>& line, double spacing) {
  std::vector<Point2> out;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const double d = std::hypot(line[i + 1].x - line[i].x, line[i + 1].y - line[i].y);
    const int n = std::max(1, static_cast<int>(std::min(std::ceil(d / spacing), kMaxDensifiedSteps)));
    for (int k = 0; k < n; ++k) {
      const double u = static_cast<double>(k) / n;
      out.push_back({line[i].x + u * (line[i + 1].x - line[i].x), line[i].y + u * (line[i + 1].y - line[i].y)});
    }
  }
  if (!line.empty()) out.push_back(line.back());
  return out;
}

bool is_vehicle_lane(const cr::Lanelet& l) {
  for (const std::string& t : l.types) {
    if (t == "sidewalk" || t == "crosswalk" || t == "bicycleLane") return false;
  }
  return true;
}

// Merges points closer than kMinPointSpacing and drops kinks sharper than
// kMaxTurnPerPoint (joints of lanelets that do not quite meet).
std::vector<Point2> cleaned(const std::vector<Point2>& raw) {
  std::vector<Point2> pts;
  for (const Point2& p : raw) {
    if (pts.empty() || std::hypot(p.x - pts.back().x, p.y - pts.back().y) >= kMinPointSpacing) {
      pts.push_back(p);
    }
  }
  if (!raw.empty() && pts.size() > 1 && std::hypot(raw.back().x - pts.back().x, raw.back().y - pts.back().y) > 0) {
    pts.back() = raw.back();  // keep the true end
  }
  bool changed = true;
  while (changed && pts.size() > 2) {
    changed = false;
    for (std::size_t i = 1; i + 1 < pts.size(); ++i) {
      const double turn = wrap_angle(heading_of(pts[i], pts[i + 1]) - heading_of(pts[i - 1], pts[i]));
      if (std::fabs(turn) > kMaxTurnPerPoint) {
        pts.erase(pts.begin() + static_cast<std::ptrdiff_t>(i));
        changed = true;
        break;
      }
    }
  }
  return pts;
}

class Network {
 public:
  explicit Network(const cr::Scenario& sc) {
    for (const cr::Lanelet& l : sc.lanelets) by_id_[l.id] = &l;
  }
  const cr::Lanelet* find(long id) const {
    const auto it = by_id_.find(id);
    return it == by_id_.end() ? nullptr : it->second;
  }
  // A referenced lanelet, or an error naming the reference.
  const cr::Lanelet* get(long id, const cr::Lanelet& from, const char* relation, std::string& error) const {
    const cr::Lanelet* l = find(id);
    if (!l && error.empty()) {
      error = fmt::format("line {}: lanelet {}: {} {} does not exist", from.line, from.id, relation, id);
    }
    return l;
  }
  const std::vector<Point2>& centre(const cr::Lanelet& l) const {
    auto it = centres_.find(l.id);
    if (it == centres_.end()) it = centres_.emplace(l.id, lanelet_centre(l)).first;
    return it->second;
  }

 private:
  std::map<long, const cr::Lanelet*> by_id_;
  mutable std::map<long, std::vector<Point2>> centres_;
};

struct EgoLanelet {
  const cr::Lanelet* lanelet = nullptr;
  double outside = 0.0;  // [m] distance outside its polygon (0 inside)
};

double distance_to_polygon(const std::vector<Point2>& poly, Point2 p) {
  if (polygon_contains(poly, p)) return 0.0;
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    d = std::min(d, point_segment_distance(p, poly[i], poly[(i + 1) % poly.size()]));
  }
  return d;
}

double length_of(const std::vector<Point2>& line) { return polyline_arc_lengths(line).back(); }

// Lanelets a goal is reached from, by successors, within kMaxGoalSearch steps
// (breadth first): the number of lanelets to the nearest goal lanelet.
std::optional<int> steps_to_goal(const Network& net, long start, const std::set<long>& goals) {
  std::vector<std::pair<long, int>> queue{{start, 0}};
  std::set<long> seen{start};
  for (std::size_t q = 0; q < queue.size() && q < static_cast<std::size_t>(kMaxGoalSearch); ++q) {
    const auto [id, depth] = queue[q];
    if (goals.count(id)) return depth;
    const cr::Lanelet* l = net.find(id);
    if (!l) continue;
    for (long s : l->successors) {
      if (seen.insert(s).second) queue.emplace_back(s, depth + 1);
    }
  }
  return std::nullopt;
}

// The lanelet holding the ego: within kEgoOutsideTolerance of its polygon and
// heading the same way (within 90 deg of its centre line at the ego). Among
// several (overlapping lanelets at junctions): vehicle lanes first, then those
// holding the ego, then those a goal lanelet is reached from, then the
// smallest heading difference, then the nearest, then the lowest id.
std::optional<EgoLanelet> find_ego_lanelet(const cr::Scenario& sc, const Network& net, const Pose& ego,
                                           const std::set<long>& goals, std::string& nearest) {
  std::optional<EgoLanelet> best;
  std::tuple<bool, bool, bool, double, double, long> best_key{};
  double nearest_d = std::numeric_limits<double>::infinity();
  for (const cr::Lanelet& l : sc.lanelets) {
    const double outside = distance_to_polygon(lanelet_polygon(l), {ego.x, ego.y});
    if (outside < nearest_d) {
      nearest_d = outside;
      nearest = fmt::format("nearest: lanelet {}, {:.2f} m away", l.id, outside);
    }
    if (outside > kEgoOutsideTolerance) continue;
    const std::vector<Point2>& c = net.centre(l);
    const PolylineProjection pr = project_to_polyline(c, ego.x, ego.y);
    const double dh = std::fabs(wrap_angle(ego.heading - pr.heading));
    if (dh >= std::numbers::pi / 2) continue;
    const bool reaches_goal = !goals.empty() && steps_to_goal(net, l.id, goals).has_value();
    const std::tuple<bool, bool, bool, double, double, long> key{!is_vehicle_lane(l), outside > 0.0, !reaches_goal,
                                                                 dh, outside, l.id};
    if (!best || key < best_key) {
      best = EgoLanelet{&l, outside};
      best_key = key;
    }
  }
  return best;
}

// Picks the next lanelet among `options` (successors, or predecessors when
// walking backwards): towards a goal when one is reachable, else the one
// continuing straightest from `heading` (its overall direction), then the lowest id.
const cr::Lanelet* choose_next(const Network& net, const cr::Lanelet& from, const std::vector<long>& options,
                               bool forward, double heading, const std::set<long>& goals, const char* relation,
                               std::string& error, std::string& note) {
  const cr::Lanelet* best = nullptr;
  std::tuple<int, double, long> best_key{};
  for (long id : options) {
    const cr::Lanelet* l = net.get(id, from, relation, error);
    if (!l) return nullptr;
    const std::vector<Point2>& c = net.centre(*l);
    const double dir = heading_of(c.front(), c.back());  // its overall driving direction
    const double turn = std::fabs(wrap_angle(dir - heading));
    const std::optional<int> to_goal = forward && !goals.empty() ? steps_to_goal(net, id, goals) : std::nullopt;
    const std::tuple<int, double, long> key{to_goal.value_or(std::numeric_limits<int>::max()), turn, id};
    if (!best || key < best_key) {
      best = l;
      best_key = key;
    }
  }
  if (best && options.size() > 1) {
    note = fmt::format("lanelet {}: {} of {} {}s taken ({})", from.id, best->id, options.size(), relation,
                       std::get<0>(best_key) != std::numeric_limits<int>::max() ? "towards the goal" : "straightest");
  }
  return best;
}

struct EdgeSample {
  double s = 0.0;
  double l = 0.0;
};

// The outer bound on one side of the road across route lanelet `start`: walk
// over neighbours (same direction; opposite ones only when allowed; no
// sidewalks, crosswalks or bicycle lanes) and return the outermost bound.
// `left` selects the side (in the route's driving direction).
const std::vector<cr::Vec2>* outer_bound(const Network& net, const cr::Lanelet& start, bool left, bool opposite_lanes,
                                         std::set<long>& road, std::string& error) {
  const cr::Lanelet* lane = &start;
  bool flipped = false;  // `lane` runs against the route
  std::set<long> seen{start.id};
  for (int k = 0; k < kMaxLanesAcross; ++k) {
    // Outwards on our left is the lane's own left unless it runs against us.
    const bool lane_left = left != flipped;
    const std::optional<cr::Neighbour>& nb = lane_left ? lane->left : lane->right;
    if (!nb) break;
    const cr::Lanelet* next = net.get(nb->id, *lane, lane_left ? "adjacentLeft" : "adjacentRight", error);
    if (!next) return nullptr;
    const bool next_flipped = flipped != (nb->direction == cr::DrivingDirection::kOpposite);
    if ((next_flipped && !opposite_lanes) || !is_vehicle_lane(*next) || !seen.insert(next->id).second) break;
    lane = next;
    flipped = next_flipped;
    road.insert(lane->id);
  }
  const bool lane_left = left != flipped;
  return lane_left ? &lane->left_bound : &lane->right_bound;
}

// Dense (s, l) samples of a polyline projected onto the reference line, in
// the polyline's order: a bound of length L with m segments gives at most
// L / kEdgeSampleSpacing + m + 1 samples, each tested against every segment
// of the reference line. The road's cost is bounded by cr::limits (its bounds,
// each projected once, total at most kMaxRoadBoundLength: at most
// 8 * 10^4 + P samples for P bound points; see formats/commonroad.hpp).
std::vector<EdgeSample> projected_samples(const std::vector<Point2>& reference, const std::vector<Point2>& line) {
  std::vector<EdgeSample> out;
  for (const Point2& p : densified(line, kEdgeSampleSpacing)) {
    const PolylineProjection pr = project_to_polyline(reference, p.x, p.y);
    out.push_back({pr.s, pr.l});
  }
  return out;
}

// Appends the samples with lo <= s <= hi.
void append_within(const std::vector<EdgeSample>& samples, double lo, double hi, std::vector<EdgeSample>& out) {
  for (const EdgeSample& e : samples) {
    if (e.s >= lo && e.s <= hi) out.push_back(e);
  }
}

using Gap = std::pair<double, double>;  // [a, b] in s

// Appends, gap after gap, the samples within each gap (as append_within for
// each gap in turn: the samples' own order within a gap). The gaps run upwards
// and meet at most at their ends (a[k+1] >= b[k] > a[k]), so a sample lies in at
// most two of them, found by a binary search on the ends: O(N log G) for N
// samples and G gaps, where scanning all samples for each gap costs N * G (a
// sparse 40 km bound: 10^4 gaps times 2 * 10^4 samples).
void append_within_gaps(const std::vector<EdgeSample>& samples, const std::vector<Gap>& gaps,
                        std::vector<EdgeSample>& out) {
  std::vector<std::pair<std::size_t, std::size_t>> hits;  // (gap, sample), in sample order
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double s = samples[i].s;  // a NaN matches no gap, as in append_within
    auto g = std::lower_bound(gaps.begin(), gaps.end(), s, [](const Gap& gap, double v) { return gap.second < v; });
    for (; g != gaps.end() && g->first <= s; ++g) hits.emplace_back(static_cast<std::size_t>(g - gaps.begin()), i);
  }
  std::stable_sort(hits.begin(), hits.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  for (const auto& hit : hits) out.push_back(samples[hit.second]);
}

// The samples of each bound the road is built from, projected onto the
// reference line once however many route lanelets use the bound (a neighbour
// beside several of them; the outer bound that is a lanelet's own): the cost
// is that of the distinct bounds, which limits::kMaxRoadBoundLength bounds.
class ProjectedBounds {
 public:
  explicit ProjectedBounds(const std::vector<Point2>& reference) : reference_(reference) {}
  const std::vector<EdgeSample>& operator()(const std::vector<cr::Vec2>& bound) {
    auto it = samples_.find(&bound);
    if (it == samples_.end()) it = samples_.emplace(&bound, projected_samples(reference_, to_points(bound))).first;
    return it->second;
  }

 private:
  const std::vector<Point2>& reference_;
  std::map<const std::vector<cr::Vec2>*, std::vector<EdgeSample>> samples_;
};

// The outer-bound samples of one route lanelet over its range [lo, hi], with
// any stretch that the outer bound does not cover (a neighbour shorter than
// the route lanelet) filled from the route lanelet's own bound on that side.
// The own bound is projected once for all gaps: a sparse outer bound has a gap
// between every two samples (fuzz_commonroad: a 40 km bound took a minute
// when each gap projected it again), and only when there is a gap.
std::vector<EdgeSample> side_samples(ProjectedBounds& projected, const std::vector<cr::Vec2>& outer,
                                     const std::vector<cr::Vec2>& own, double lo, double hi) {
  std::vector<EdgeSample> out;
  append_within(projected(outer), lo, hi, out);
  std::sort(out.begin(), out.end(), [](const EdgeSample& a, const EdgeSample& b) { return a.s < b.s; });
  std::vector<Gap> gaps;
  double covered = lo;
  for (const EdgeSample& e : out) {
    if (e.s - covered > 2 * kEdgeSampleSpacing) gaps.emplace_back(covered, e.s);
    covered = std::max(covered, e.s);
  }
  if (hi - covered > 2 * kEdgeSampleSpacing) gaps.emplace_back(covered, hi);
  if (gaps.empty()) return out;
  append_within_gaps(projected(own), gaps, out);
  return out;
}

// The innermost l of a run of samples (left edge: the least, right edge: the
// greatest), the one that folding std::min / std::max over the run in order
// picks: the first innermost sample, NaNs passed over unless the run starts
// with one (the fold then stays NaN). A segment tree of the picked indices
// answers a run in O(log N) where the fold costs its length: a cluster of
// 8 * 10^4 samples at one s (a 10 km bound across the road's start) was folded
// again by each of the 10^4 knots that widened to it.
class InnermostOfRun {
 public:
  // `samples` must outlive this.
  InnermostOfRun(const std::vector<EdgeSample>& samples, bool left)
      : samples_(samples), left_(left), tree_(2 * samples.size()) {
    const std::size_t n = samples.size();
    for (std::size_t i = 0; i < n; ++i) tree_[n + i] = i;
    for (std::size_t i = n; i-- > 1;) tree_[i] = pick(tree_[2 * i], tree_[2 * i + 1]);
  }

  // The samples [first, last), first < last.
  double operator()(std::size_t first, std::size_t last) const {
    if (std::isnan(samples_[first].l)) return samples_[first].l;
    // Bottom-up over the tree, keeping the picks from the left and from the
    // right apart: pick() takes the earlier sample first.
    std::size_t from_left = kNone, from_right = kNone;
    for (std::size_t a = first + samples_.size(), b = last + samples_.size(); a < b; a /= 2, b /= 2) {
      if (a % 2 == 1) from_left = pick(from_left, tree_[a++]);
      if (b % 2 == 1) from_right = pick(tree_[--b], from_right);
    }
    return samples_[pick(from_left, from_right)].l;
  }

 private:
  static constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

  // x strictly inner than `than`; a NaN is inner than nothing, anything else is inner than a NaN.
  bool inner(double x, double than) const {
    if (std::isnan(x)) return false;
    if (std::isnan(than)) return true;
    return left_ ? x < than : x > than;
  }
  // Of samples a and b (a before b, either may be kNone): b only if strictly inner.
  std::size_t pick(std::size_t a, std::size_t b) const {
    if (a == kNone) return b;
    if (b == kNone) return a;
    return inner(samples_[b].l, samples_[a].l) ? b : a;
  }

  const std::vector<EdgeSample>& samples_;
  bool left_;
  std::vector<std::size_t> tree_;  // node k covers nodes 2k and 2k + 1; the leaves n + i hold i
};

// The indices [first, last) of the samples (sorted by s) with lo <= s <= hi.
std::pair<std::size_t, std::size_t> run_within(const std::vector<EdgeSample>& samples, double lo, double hi) {
  const auto first = std::lower_bound(samples.begin(), samples.end(), lo,
                                      [](const EdgeSample& e, double v) { return e.s < v; });
  const auto last = std::upper_bound(first, samples.end(), hi, [](double v, const EdgeSample& e) { return v < e.s; });
  return {static_cast<std::size_t>(first - samples.begin()), static_cast<std::size_t>(last - samples.begin())};
}

// [s, l] knots every kEdgeKnotSpacing m, each at the innermost sample within
// one spacing on either side: the linear edge between two knots then lies
// inside every sample between them (left: min l, right: max l).
Boundary edge_from_samples(std::vector<EdgeSample> samples, double length, bool left) {
  std::sort(samples.begin(), samples.end(), [](const EdgeSample& a, const EdgeSample& b) { return a.s < b.s; });
  Boundary b;
  if (samples.empty()) return b;
  const InnermostOfRun innermost(samples, left);
  const int n = std::max(1, static_cast<int>(std::ceil(length / kEdgeKnotSpacing)));
  const double h = length / n;
  for (int j = 0; j <= n; ++j) {
    const double s = h * j;
    double reach = h;
    std::optional<double> inner;
    while (!inner) {  // widen until a sample is found (only where samples are sparse)
      const auto [first, last] = run_within(samples, s - reach, s + reach);
      if (first < last) inner = innermost(first, last);
      reach *= 2.0;
    }
    b.knots.push_back({s, *inner});
  }
  return b;
}

}  // namespace

std::vector<Point2> lanelet_centre(const cr::Lanelet& l) {
  std::vector<Point2> out;
  const std::vector<Point2> left = to_points(l.left_bound);
  const std::vector<Point2> right = to_points(l.right_bound);
  if (left.size() == right.size()) {
    for (std::size_t i = 0; i < left.size(); ++i) out.push_back({0.5 * (left[i].x + right[i].x), 0.5 * (left[i].y + right[i].y)});
    return out;
  }
  const std::vector<double> al = polyline_arc_lengths(left);
  const std::vector<double> ar = polyline_arc_lengths(right);
  const std::size_t n = std::max(left.size(), right.size());
  for (std::size_t i = 0; i < n; ++i) {
    const double u = static_cast<double>(i) / static_cast<double>(n - 1);
    const Point2 a = al.back() > 0 ? at_fraction(left, al, u) : left.front();
    const Point2 b = ar.back() > 0 ? at_fraction(right, ar, u) : right.front();
    out.push_back({0.5 * (a.x + b.x), 0.5 * (a.y + b.y)});
  }
  return out;
}

std::vector<Point2> lanelet_polygon(const cr::Lanelet& l) {
  std::vector<Point2> poly = to_points(l.left_bound);
  for (auto it = l.right_bound.rbegin(); it != l.right_bound.rend(); ++it) poly.push_back(to_point(*it));
  return poly;
}

bool polygon_contains(const std::vector<Point2>& poly, Point2 p) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Point2& a = poly[i];
    const Point2& b = poly[j];
    if (point_segment_distance(p, a, b) <= 1e-9) return true;
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

RouteResult build_route(const cr::Scenario& sc, const Pose& ego, const RouteOptions& opt) {
  RouteResult res;
  if (sc.lanelets.empty()) {
    res.error = "the scenario has no <lanelet>: there is no road to drive on";
    return res;
  }
  const Network net(sc);
  const std::set<long> goals(opt.goal_lanelets.begin(), opt.goal_lanelets.end());
  std::string nearest;
  const std::optional<EgoLanelet> ego_lanelet = find_ego_lanelet(sc, net, ego, goals, nearest);
  if (!ego_lanelet) {
    res.error = fmt::format(
        "the ego at ({:.2f}, {:.2f}), heading {:.3f} rad, lies in no lanelet that runs its way "
        "(within {} m; {})",
        ego.x, ego.y, ego.heading, kEgoOutsideTolerance, nearest);
    return res;
  }
  LaneRoute route;
  std::string error;
  for (long g : goals) {
    if (!net.find(g)) {
      res.error = fmt::format("planningProblem goalState: goal lanelet {} does not exist", g);
      return res;
    }
  }

  // Forward through successors from the ego's lanelet.
  const cr::Lanelet* ego_l = ego_lanelet->lanelet;
  const double s_in_ego = project_to_polyline(net.centre(*ego_l), ego.x, ego.y).s;
  std::vector<const cr::Lanelet*> ahead{ego_l};
  std::set<long> used{ego_l->id};
  double covered = length_of(net.centre(*ego_l)) - s_in_ego;
  while (covered < opt.length_ahead && !ahead.back()->successors.empty()) {
    const cr::Lanelet& cur = *ahead.back();
    const std::vector<Point2>& c = net.centre(cur);
    std::string note;
    const cr::Lanelet* next = choose_next(net, cur, cur.successors, true, heading_of(c[c.size() - 2], c.back()), goals,
                                          "successor", error, note);
    if (!next) break;
    if (!used.insert(next->id).second) {
      route.notes.push_back(fmt::format("lanelet {}: the route comes back to lanelet {}; it ends there", cur.id, next->id));
      break;
    }
    if (!note.empty()) route.notes.push_back(note);
    ahead.push_back(next);
    covered += length_of(net.centre(*next));
  }
  // Backward through predecessors, so the line starts behind the ego.
  std::vector<const cr::Lanelet*> behind;
  covered = s_in_ego;
  const cr::Lanelet* cur = ego_l;
  while (error.empty() && covered < opt.length_behind && !cur->predecessors.empty()) {
    const std::vector<Point2>& c = net.centre(*cur);
    std::string note;
    const cr::Lanelet* prev =
        choose_next(net, *cur, cur->predecessors, false, heading_of(c.front(), c[1]), {}, "predecessor", error, note);
    if (!prev || !used.insert(prev->id).second) break;
    behind.push_back(prev);
    covered += length_of(net.centre(*prev));
    cur = prev;
  }
  if (!error.empty()) {
    res.error = error;
    return res;
  }
  std::vector<const cr::Lanelet*> lanes(behind.rbegin(), behind.rend());
  route.ego_index = lanes.size();
  lanes.insert(lanes.end(), ahead.begin(), ahead.end());

  std::vector<Point2> raw;
  for (const cr::Lanelet* l : lanes) {
    route.lanelets.push_back(l->id);
    for (const Point2& p : net.centre(*l)) {
      if (raw.empty() || std::hypot(p.x - raw.back().x, p.y - raw.back().y) > 1e-6) raw.push_back(p);
    }
  }
  route.reference_line = cleaned(raw);
  if (route.reference_line.size() < 2) {
    res.error = fmt::format("lanelet {}: the route's centre line is shorter than {} m", ego_l->id, kMinPointSpacing);
    return res;
  }
  const std::vector<double> arc = polyline_arc_lengths(route.reference_line);
  if (arc.back() > cr::limits::kMaxRouteLength) {
    res.error = fmt::format(
        "lanelet {}: the route from the ego's lanelet through {} lanelets ({} to {}) is {:.1f} m long; the importer's "
        "limit for a route is {:g} m",
        ego_l->id, lanes.size(), lanes.front()->id, lanes.back()->id, arc.back(), cr::limits::kMaxRouteLength);
    return res;
  }

  // The outermost bounds on each side of each route lanelet, and the bounds
  // the road is built from within their limit.
  std::vector<std::pair<const std::vector<cr::Vec2>*, const std::vector<cr::Vec2>*>> outer;
  std::set<long> road(route.lanelets.begin(), route.lanelets.end());
  for (const cr::Lanelet* l : lanes) {
    const auto* outer_left = outer_bound(net, *l, true, opt.opposite_lanes, road, error);
    const auto* outer_right = outer_bound(net, *l, false, opt.opposite_lanes, road, error);
    if (!outer_left || !outer_right) {
      res.error = error;
      return res;
    }
    outer.emplace_back(outer_left, outer_right);
  }
  std::set<const std::vector<cr::Vec2>*> bounds;
  double bounds_length = 0.0;
  const std::vector<cr::Vec2>* longest = nullptr;
  double longest_length = 0.0;
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    for (const auto* b : {outer[i].first, outer[i].second, &lanes[i]->left_bound, &lanes[i]->right_bound}) {
      if (!bounds.insert(b).second) continue;
      const double length = length_of(to_points(*b));
      bounds_length += length;
      if (length > longest_length) {
        longest = b;
        longest_length = length;
      }
    }
  }
  if (bounds_length > cr::limits::kMaxRoadBoundLength) {
    std::string which;
    for (const cr::Lanelet& l : sc.lanelets) {
      if (longest == &l.left_bound || longest == &l.right_bound) {
        which = fmt::format("lanelet {} {}", l.id, longest == &l.left_bound ? "leftBound" : "rightBound");
      }
    }
    res.error = fmt::format(
        "lanelet {}: the road along the route is built from {} lanelet bounds (the route lanelets' own and the "
        "outermost ones beside them) of {:.1f} m in all, the longest {}, {:.1f} m; the importer's limit is {:g} m",
        ego_l->id, bounds.size(), bounds_length, which, longest_length, cr::limits::kMaxRoadBoundLength);
    return res;
  }

  // The drivable area across each route lanelet, over its s-range.
  std::vector<EdgeSample> left_samples, right_samples;
  ProjectedBounds projected(route.reference_line);
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    const cr::Lanelet* l = lanes[i];
    const std::vector<Point2>& c = net.centre(*l);
    const double lo = project_to_polyline(route.reference_line, c.front().x, c.front().y).s;
    const double hi = project_to_polyline(route.reference_line, c.back().x, c.back().y).s;
    for (const auto& e : side_samples(projected, *outer[i].first, l->left_bound, lo, hi)) left_samples.push_back(e);
    for (const auto& e : side_samples(projected, *outer[i].second, l->right_bound, lo, hi)) right_samples.push_back(e);
  }
  if (left_samples.empty() || right_samples.empty()) {
    res.error = fmt::format("lanelet {}: the bounds of the route's lanelets do not project onto its centre line", ego_l->id);
    return res;
  }
  route.left = edge_from_samples(left_samples, arc.back(), true);
  route.right = edge_from_samples(right_samples, arc.back(), false);
  route.road_lanelets.assign(road.begin(), road.end());

  // The ego lanelet's width at the ego.
  const double wl = project_to_polyline(to_points(ego_l->left_bound), ego.x, ego.y).l;
  const double wr = project_to_polyline(to_points(ego_l->right_bound), ego.x, ego.y).l;
  route.lane_width = std::fabs(wl - wr);
  res.route = std::move(route);
  return res;
}

}  // namespace hil::sim
