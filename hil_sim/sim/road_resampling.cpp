#include "sim/road_resampling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "sim/box_geometry.hpp"

namespace hil::sim {
namespace {

using Knot = Boundary::Knot;
constexpr int kBisections = 40;

// The truth on [s_begin, s_end] as knots: its value at both ends and its own
// knots strictly between them.
std::vector<Knot> restrict_to(std::span<const Knot> truth, double s_begin, double s_end) {
  std::vector<Knot> out{{s_begin, edge_at(truth, s_begin)}};
  for (const Knot& k : truth) {
    if (k.s > s_begin && k.s < s_end) out.push_back(k);
  }
  if (s_end > s_begin) out.push_back({s_end, edge_at(truth, s_end)});
  return out;
}

// Greedy segments inside the band [truth - tol, truth] (left edge). Both are
// piecewise linear with breaks at the truth's knots, and the fit's knots are
// placed at truth knots, so the band need only hold at the truth's knots.
// From the current knot (s_i, f_i), a slope m keeps knot k > i in the band iff
// (l_k - tol - f_i) / (s_k - s_i) <= m <= (l_k - f_i) / (s_k - s_i): the
// feasible slopes for reaching j form an interval, narrowed as j advances.
// The segment ends at the last knot the interval reaches, with the middle
// slope; the next one starts there. The first knot starts tol/2 below the
// truth. Returns the knots, or nothing when more than max_knots are needed.
std::optional<std::vector<Knot>> band_segments(const std::vector<Knot>& t, double tol, std::size_t max_knots) {
  std::vector<Knot> out{{t.front().s, t.front().l - 0.5 * tol}};
  std::size_t i = 0;
  while (i + 1 < t.size()) {
    const Knot from = out.back();
    double lower = -std::numeric_limits<double>::infinity();
    double upper = std::numeric_limits<double>::infinity();
    std::size_t last = i + 1;
    for (std::size_t j = i + 1; j < t.size(); ++j) {
      const double ds = t[j].s - from.s;
      const double lo = std::max(lower, (t[j].l - tol - from.l) / ds);
      const double hi = std::min(upper, (t[j].l - from.l) / ds);
      if (lo > hi && j > i + 1) break;
      lower = lo;
      upper = std::max(lo, hi);  // the first knot is always reachable (rounding aside)
      last = j;
    }
    const double m = 0.5 * (lower + upper);
    // Never above the truth, whatever the rounding.
    out.push_back({t[last].s, std::min(t[last].l, from.l + m * (t[last].s - from.s))});
    if (out.size() > max_knots) return std::nullopt;
    i = last;
  }
  return out;
}

// max_knots knots on a uniform grid, each at the truth's minimum over its two
// neighbouring intervals, so both ends of every fit segment lie below the
// truth's minimum over that segment.
std::vector<Knot> uniform_envelope(const std::vector<Knot>& t, std::size_t max_knots) {
  const double s0 = t.front().s;
  const double s1 = t.back().s;
  const double h = (s1 - s0) / static_cast<double>(max_knots - 1);
  std::vector<Knot> out;
  for (std::size_t j = 0; j < max_knots; ++j) {
    const double s = j + 1 == max_knots ? s1 : s0 + h * static_cast<double>(j);
    const double lo = std::max(s0, s - h);
    const double hi = std::min(s1, s + h);
    double l = std::min(edge_at(t, lo), edge_at(t, hi));
    for (const Knot& k : t) {
      if (k.s > lo && k.s < hi) l = std::min(l, k.l);
    }
    out.push_back({s, l});
  }
  return out;
}

std::vector<Knot> mirrored(std::span<const Knot> knots) {
  std::vector<Knot> out(knots.begin(), knots.end());
  for (Knot& k : out) k.l = -k.l;
  return out;
}

}  // namespace

double edge_at(std::span<const Knot> knots, double s) {
  if (knots.empty()) return 0.0;
  if (s <= knots.front().s) return knots.front().l;
  if (s >= knots.back().s) return knots.back().l;
  const auto it = std::upper_bound(knots.begin(), knots.end(), s, [](double v, const Knot& k) { return v < k.s; });
  const Knot& b = *it;
  const Knot& a = *(it - 1);
  return a.l + (s - a.s) / (b.s - a.s) * (b.l - a.l);
}

double max_edge_gap(std::span<const Knot> truth, std::span<const Knot> fit, double s_begin, double s_end) {
  double gap = std::max(std::fabs(edge_at(truth, s_begin) - edge_at(fit, s_begin)),
                        std::fabs(edge_at(truth, s_end) - edge_at(fit, s_end)));
  for (const auto& set : {truth, fit}) {
    for (const Knot& k : set) {
      if (k.s > s_begin && k.s < s_end) gap = std::max(gap, std::fabs(edge_at(truth, k.s) - edge_at(fit, k.s)));
    }
  }
  return gap;
}

EdgeFit fit_edge_inside(std::span<const Knot> truth, double s_begin, double s_end, int max_knots, EdgeSide side) {
  // The right edge is the left edge of the mirrored road (l -> -l).
  const std::vector<Knot> as_left = side == EdgeSide::kLeft ? std::vector<Knot>(truth.begin(), truth.end()) : mirrored(truth);
  const std::vector<Knot> t = restrict_to(as_left, s_begin, s_end);
  const std::size_t budget = static_cast<std::size_t>(std::max(1, max_knots));
  EdgeFit fit;
  if (t.size() <= budget) {
    fit.knots = t;
  } else if (budget == 1) {
    double l = t.front().l;
    for (const Knot& k : t) l = std::min(l, k.l);
    fit.knots = {{s_begin, l}};
  } else {
    std::vector<Knot> best = uniform_envelope(t, budget);
    double best_gap = max_edge_gap(t, best, s_begin, s_end);
    double lo = 0.0;
    double hi = 0.0;
    for (const Knot& k : t) hi = std::max(hi, std::fabs(k.l - t.front().l));
    hi = 2.0 * hi + 1.0;
    if (band_segments(t, hi, budget)) {
      for (int it = 0; it < kBisections; ++it) {
        const double mid = 0.5 * (lo + hi);
        (band_segments(t, mid, budget) ? hi : lo) = mid;
      }
      std::vector<Knot> chords = *band_segments(t, hi, budget);
      const double gap = max_edge_gap(t, chords, s_begin, s_end);
      if (gap < best_gap) {
        best = std::move(chords);
        best_gap = gap;
      }
    }
    fit.knots = std::move(best);
  }
  fit.max_narrowing = max_edge_gap(t, fit.knots, s_begin, s_end);
  if (side == EdgeSide::kRight) fit.knots = mirrored(fit.knots);
  return fit;
}

namespace {

// Greedy vertex subset: the farthest next vertex whose chord is <= max_chord
// long and keeps every skipped vertex within tol. Stops extending at the first
// chord that fails. Nothing when more than max_points would be needed.
std::optional<std::vector<std::size_t>> greedy_vertices(std::span<const Point2> line, double tol, double max_chord,
                                                        std::size_t max_points) {
  std::vector<std::size_t> kept{0};
  std::size_t i = 0;
  while (i + 1 < line.size()) {
    std::size_t best = i + 1;
    for (std::size_t j = i + 2; j < line.size(); ++j) {
      if (std::hypot(line[j].x - line[i].x, line[j].y - line[i].y) > max_chord) break;
      bool ok = true;
      for (std::size_t k = i + 1; k < j && ok; ++k) ok = point_segment_distance(line[k], line[i], line[j]) <= tol;
      if (!ok) break;
      best = j;
    }
    kept.push_back(best);
    if (kept.size() > max_points) return std::nullopt;
    i = best;
  }
  return kept;
}

double deviation(std::span<const Point2> line, const std::vector<std::size_t>& kept) {
  double d = 0.0;
  for (std::size_t a = 0; a + 1 < kept.size(); ++a) {
    for (std::size_t k = kept[a] + 1; k < kept[a + 1]; ++k) {
      d = std::max(d, point_segment_distance(line[k], line[kept[a]], line[kept[a + 1]]));
    }
  }
  return d;
}

}  // namespace

PolylineFit simplify_polyline(std::span<const Point2> line, int max_points, double max_chord) {
  PolylineFit fit;
  const std::size_t budget = static_cast<std::size_t>(std::max(2, max_points));
  if (line.size() <= budget) {
    fit.points.assign(line.begin(), line.end());
    return fit;
  }
  // Chords longer than max_chord are allowed only if the budget cannot be met otherwise.
  double chord = max_chord;
  double hi = 0.0;
  for (const Point2& p : line) hi = std::max(hi, std::hypot(p.x - line.front().x, p.y - line.front().y));
  hi = 2.0 * hi + 1.0;
  while (!greedy_vertices(line, hi, chord, budget)) chord = chord * 2.0 > hi ? std::numeric_limits<double>::infinity() : chord * 2.0;
  double lo = 0.0;
  for (int it = 0; it < kBisections; ++it) {
    const double mid = 0.5 * (lo + hi);
    (greedy_vertices(line, mid, chord, budget) ? hi : lo) = mid;
  }
  const std::vector<std::size_t> kept = *greedy_vertices(line, hi, chord, budget);
  for (std::size_t k : kept) fit.points.push_back(line[k]);
  fit.max_deviation = deviation(line, kept);
  return fit;
}

}  // namespace hil::sim
