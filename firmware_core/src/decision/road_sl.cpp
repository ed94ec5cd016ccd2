#include "itp/decision/road_sl.hpp"

#include <array>

#include "itp/configurations.hpp"

namespace itp::decision {

template <class Cfg>
BasicLateralProfile<Cfg> BasicLateralProfile<Cfg>::constant(Scalar l) {
  BasicLateralProfile p;
  static_cast<void>(p.add(Scalar(0), l));  // the first point of an empty profile
  return p;
}

template <class Cfg>
bool BasicLateralProfile<Cfg>::add(Scalar s, Scalar l) {
  if (!points_.empty() && !(s > points_.back().s)) {
    return false;
  }
  return points_.push_back(Point{s, l});
}

template <class Cfg>
Scalar BasicLateralProfile<Cfg>::at(Scalar s) const {
  const std::size_t n = points_.size();
  if (n == 0) {
    return Scalar(0);
  }
  if (s <= points_[0].s) {
    return points_[0].l;
  }
  for (std::size_t i = 1; i < n; ++i) {  // n <= kMaxBoundaryPoints
    if (s <= points_[i].s) {
      const Point& a = points_[i - 1];
      const Point& b = points_[i];
      const Scalar u = (s - a.s) / (b.s - a.s);
      return a.l + u * (b.l - a.l);
    }
  }
  return points_[n - 1].l;
}

template <class Cfg>
Scalar BasicLateralProfile<Cfg>::min_over(Scalar s0, Scalar s1) const {
  Scalar m = at(s0) < at(s1) ? at(s0) : at(s1);
  for (const Point& p : points_) {  // kMaxBoundaryPoints
    if (p.s > s0 && p.s < s1 && p.l < m) {
      m = p.l;
    }
  }
  return m;
}

template <class Cfg>
Scalar BasicLateralProfile<Cfg>::max_over(Scalar s0, Scalar s1) const {
  Scalar m = at(s0) > at(s1) ? at(s0) : at(s1);
  for (const Point& p : points_) {  // kMaxBoundaryPoints
    if (p.s > s0 && p.s < s1 && p.l > m) {
      m = p.l;
    }
  }
  return m;
}

namespace {

// Width lost to the edges' variation over the points [a, b] (both edges are
// linear between consecutive points, so their extremes are at points).
Scalar lost_width(const Scalar* lo, const Scalar* hi, int a, int b) {
  Scalar lo_min = lo[a];
  Scalar lo_max = lo[a];
  Scalar hi_min = hi[a];
  Scalar hi_max = hi[a];
  for (int k = a + 1; k <= b; ++k) {  // <= the points of select_road_cuts
    lo_min = lo[k] < lo_min ? lo[k] : lo_min;
    lo_max = lo[k] > lo_max ? lo[k] : lo_max;
    hi_min = hi[k] < hi_min ? hi[k] : hi_min;
    hi_max = hi[k] > hi_max ? hi[k] : hi_max;
  }
  return (lo_max - lo_min) + (hi_max - hi_min);
}

}  // namespace

template <class Cfg>
void select_road_cuts(BasicRoadSl<Cfg>& road, Scalar s0, Scalar s1, Scalar tolerance, Scalar min_length) {
  road.cuts.clear();
  if (!(s1 > s0)) {
    return;
  }
  // The ends, every knot of either edge between them, and the middles added
  // by splits of straight stretches.
  constexpr std::size_t kPoints = 2 * Cfg::kMaxBoundaryPoints + 2 + Cfg::kMaxRoadCuts;
  std::array<Scalar, kPoints> s{};
  std::array<Scalar, kPoints> lo{};
  std::array<Scalar, kPoints> hi{};
  int n = 0;
  s[static_cast<std::size_t>(n++)] = s0;
  const auto right = road.right.points();
  const auto left = road.left.points();
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < right.size() || j < left.size()) {  // <= 2 kMaxBoundaryPoints: merge of two sorted lists
    const bool take_right = j >= left.size() || (i < right.size() && right[i].s <= left[j].s);
    const Scalar v = take_right ? right[i++].s : left[j++].s;
    if (v > s0 && v < s1 && v > s[static_cast<std::size_t>(n - 1)]) {
      s[static_cast<std::size_t>(n++)] = v;
    }
  }
  s[static_cast<std::size_t>(n++)] = s1;
  for (int k = 0; k < n; ++k) {  // < kPoints
    lo[static_cast<std::size_t>(k)] = road.right.at(s[static_cast<std::size_t>(k)]);
    hi[static_cast<std::size_t>(k)] = road.left.at(s[static_cast<std::size_t>(k)]);
  }
  // Slice edges as point indices, ascending.
  std::array<int, Cfg::kMaxRoadCuts + 2> edge{};
  int edges = 0;
  edge[static_cast<std::size_t>(edges++)] = 0;
  edge[static_cast<std::size_t>(edges++)] = n - 1;
  for (int round = 0; round < Cfg::kMaxRoadCuts; ++round) {  // one cut per round
    // The slice losing the most area.
    int worst = -1;
    Scalar worst_area = 0;
    for (int e = 0; e + 1 < edges; ++e) {  // <= kMaxRoadCuts + 1 slices
      const int a = edge[static_cast<std::size_t>(e)];
      const int b = edge[static_cast<std::size_t>(e + 1)];
      const Scalar length = s[static_cast<std::size_t>(b)] - s[static_cast<std::size_t>(a)];
      const Scalar lost = lost_width(lo.data(), hi.data(), a, b);
      if (lost > tolerance && length >= Scalar(2) * min_length && lost * length > worst_area) {
        worst = e;
        worst_area = lost * length;
      }
    }
    if (worst < 0) {
      break;
    }
    const int a = edge[static_cast<std::size_t>(worst)];
    int b = edge[static_cast<std::size_t>(worst + 1)];
    // Split at the interior point that loses the least area, both halves at
    // least min_length long.
    int split = -1;
    Scalar best = 0;
    for (int m = a + 1; m < b; ++m) {  // < kPoints
      const Scalar sm = s[static_cast<std::size_t>(m)];
      if (sm - s[static_cast<std::size_t>(a)] < min_length || s[static_cast<std::size_t>(b)] - sm < min_length) {
        continue;
      }
      const Scalar area = (sm - s[static_cast<std::size_t>(a)]) * lost_width(lo.data(), hi.data(), a, m) +
                          (s[static_cast<std::size_t>(b)] - sm) * lost_width(lo.data(), hi.data(), m, b);
      if (split < 0 || area < best) {
        split = m;
        best = area;
      }
    }
    if (split < 0 || !(best < worst_area)) {
      // No knot helps: a straight stretch, split in the middle (a new point).
      if (n >= static_cast<int>(kPoints)) {
        break;
      }
      const Scalar mid = Scalar(0.5) * (s[static_cast<std::size_t>(a)] + s[static_cast<std::size_t>(b)]);
      split = a + 1;
      while (split < b && s[static_cast<std::size_t>(split)] < mid) {  // < kPoints
        ++split;
      }
      for (int k = n; k > split; --k) {  // < kPoints: make room
        s[static_cast<std::size_t>(k)] = s[static_cast<std::size_t>(k - 1)];
        lo[static_cast<std::size_t>(k)] = lo[static_cast<std::size_t>(k - 1)];
        hi[static_cast<std::size_t>(k)] = hi[static_cast<std::size_t>(k - 1)];
      }
      ++n;
      s[static_cast<std::size_t>(split)] = mid;
      lo[static_cast<std::size_t>(split)] = road.right.at(mid);
      hi[static_cast<std::size_t>(split)] = road.left.at(mid);
      for (int e = worst + 1; e < edges; ++e) {  // <= kMaxRoadCuts + 2: indices behind the new point
        ++edge[static_cast<std::size_t>(e)];
      }
      b = edge[static_cast<std::size_t>(worst + 1)];
    }
    for (int e = edges; e > worst + 1; --e) {  // <= kMaxRoadCuts + 2: insert the new edge
      edge[static_cast<std::size_t>(e)] = edge[static_cast<std::size_t>(e - 1)];
    }
    edge[static_cast<std::size_t>(worst + 1)] = split;
    ++edges;
    static_cast<void>(b);
  }
  for (int e = 1; e + 1 < edges; ++e) {  // <= kMaxRoadCuts
    // Cleared above; interior edges = edges - 2 <= kMaxRoadCuts = capacity.
    static_cast<void>(road.cuts.push_back(s[static_cast<std::size_t>(edge[static_cast<std::size_t>(e)])]));
  }
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C)                     \
  template class BasicLateralProfile<C>;       \
  template void select_road_cuts<C>(BasicRoadSl<C>&, Scalar, Scalar, Scalar, Scalar);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::decision
