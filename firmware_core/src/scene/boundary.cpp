#include <bit>

#include "itp/configurations.hpp"
#include "itp/scene/scene.hpp"

namespace itp::scene {

template <class Cfg>
Scalar BasicBoundary<Cfg>::at(Scalar s) const {
  const int n = static_cast<int>(table.size());
  if (n == 0) {
    return offset;
  }
  if (s <= table[0].s) {
    return table[0].l;
  }
  if (s >= table.back().s) {
    return table.back().l;
  }
  constexpr int kSteps =
      static_cast<int>(std::bit_width(static_cast<unsigned>(Cfg::kMaxBoundaryPoints))) + 1;
  int lo = 0;
  int hi = n - 1;
  for (int step = 0; step < kSteps && hi - lo > 1; ++step) {
    const int mid = (lo + hi) / 2;
    if (table[static_cast<std::size_t>(mid)].s <= s) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  const BoundaryPoint a = table[static_cast<std::size_t>(lo)];
  const BoundaryPoint b = table[static_cast<std::size_t>(hi)];
  return a.l + (b.l - a.l) * (s - a.s) / (b.s - a.s);
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C) template struct BasicBoundary<C>;
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::scene
