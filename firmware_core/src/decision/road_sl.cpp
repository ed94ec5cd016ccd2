#include "itp/decision/road_sl.hpp"

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

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C) template class BasicLateralProfile<C>;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::decision
