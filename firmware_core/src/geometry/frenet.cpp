#include "itp/geometry/frenet.hpp"

#include <algorithm>
#include <cmath>

#include "itp/configurations.hpp"
#include "itp/geometry/angle.hpp"

namespace itp::geometry {

Scalar relative_heading(Scalar heading, Scalar ref_heading) {
  return wrap_angle(heading - ref_heading);
}

Scalar lateral_slope(Scalar heading, Scalar ref_heading, Scalar ref_kappa, Scalar l) {
  return (Scalar(1) - ref_kappa * l) * std::tan(relative_heading(heading, ref_heading));
}

Scalar heading_from_lateral_slope(Scalar l_prime, Scalar ref_heading, Scalar ref_kappa,
                                  Scalar l) {
  return wrap_angle(ref_heading + std::atan2(l_prime, Scalar(1) - ref_kappa * l));
}

CartesianMotion cartesian_motion(const FrenetState& f) {
  const Scalar q = Scalar(1) - f.ref_kappa * f.l;
  const Scalar q_s = -(f.ref_dkappa * f.l + f.ref_kappa * f.dl);
  const Scalar g2 = q * q + f.dl * f.dl;
  const Scalar g = std::sqrt(g2);
  const Scalar g_s = (q * q_s + f.dl * f.ddl) / g;
  CartesianMotion m;
  m.relative_heading = std::atan2(f.dl, q);
  m.kappa = (f.ref_kappa + (q * f.ddl - f.dl * q_s) / g2) / g;
  m.v = f.ds * g;
  m.a = f.dds * g + f.ds * f.ds * g_s;
  m.scale = g;
  return m;
}

CartesianState to_cartesian(const CurveSample& ref, FrenetState f) {
  f.ref_kappa = ref.kappa;
  f.ref_dkappa = ref.dkappa;
  const CartesianMotion m = cartesian_motion(f);
  CartesianState c;
  c.position.x = ref.position.x - f.l * std::sin(ref.heading);
  c.position.y = ref.position.y + f.l * std::cos(ref.heading);
  c.heading = wrap_angle(ref.heading + m.relative_heading);
  c.kappa = m.kappa;
  c.v = m.v;
  c.a = m.a;
  return c;
}

FrenetState to_frenet_state(const CurveSample& ref, Scalar l, const CartesianState& c) {
  const Scalar q = Scalar(1) - ref.kappa * l;
  const Scalar cos_dtheta = std::cos(relative_heading(c.heading, ref.heading));
  FrenetState f;
  f.l = l;
  f.dl = lateral_slope(c.heading, ref.heading, ref.kappa, l);
  f.ddl = (c.kappa * q / cos_dtheta - ref.kappa) * q / (cos_dtheta * cos_dtheta);
  f.ds = c.v * cos_dtheta / q;
  f.dds = c.a * cos_dtheta / q;
  f.ref_kappa = ref.kappa;
  f.ref_dkappa = ref.dkappa;
  return f;
}

template <class Cfg>
SlBox sl_bounding_box(const BasicReferenceLine<Cfg>& line, const OrientedBox& box, Scalar margin) {
  // Edge k runs from corner k to corner k+1 (counter-clockwise).
  const std::array<Point2, 4> corners = geometry::corners(box);
  const FrenetPoint first = line.to_frenet(corners[0]);
  SlBox out{first.s, first.s, first.l, first.l};
  for (std::size_t k = 0; k < 4; ++k) {  // 4 edges
    const Point2 a = corners[k];
    const Point2 edge = corners[(k + 1) % 4] - a;
    // Samples at j / pieces of the edge, j = 0 .. pieces-1 (the corner k+1 is
    // the next edge's first sample).
    const Scalar pieces_real = std::ceil(norm(edge) / config::kBoxEdgeSampleSpacing);
    const int pieces = std::clamp(static_cast<int>(pieces_real), 1, config::kMaxBoxEdgeSamples);
    for (int j = 0; j < config::kMaxBoxEdgeSamples && j < pieces; ++j) {
      const Scalar f = static_cast<Scalar>(j) / static_cast<Scalar>(pieces);
      const FrenetPoint q = line.to_frenet(a + f * edge);
      out.s_min = std::min(out.s_min, q.s);
      out.s_max = std::max(out.s_max, q.s);
      out.l_min = std::min(out.l_min, q.l);
      out.l_max = std::max(out.l_max, q.l);
    }
  }
  out.s_min -= margin;
  out.s_max += margin;
  out.l_min -= margin;
  out.l_max += margin;
  return out;
}

// Explicit instantiations for every configuration (itp/configurations.hpp).
#define ITP_INSTANTIATE(C) \
  template SlBox sl_bounding_box<C>(const BasicReferenceLine<C>&, const OrientedBox&, Scalar);
ITP_FOR_EACH_CONFIG(ITP_INSTANTIATE)
#undef ITP_INSTANTIATE

}  // namespace itp::geometry
